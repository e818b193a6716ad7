# Install rules and the package config that makes find_package(frnn) work.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)
install(TARGETS frnn EXPORT frnnTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# The installed headers, by name: a header in include/frnn is public once it is listed here.
# The Vulkan backend installs its own (vulkan.hpp, grid.glsl) with its component, and so does
# the MPI layer (mpi/).
set(frnn_public_headers
  brute_force.hpp buffer.hpp csr.hpp error.hpp frnn.hpp grid.hpp grid_geometry.hpp lattice.hpp options.hpp
  parallel.hpp periodic_wrap.hpp point_sets.hpp search_scale.hpp simd.hpp verlet_lists.hpp
  detail/candidate_runs.hpp detail/grid_storage.hpp detail/stopwatch.hpp)
set(frnn_vulkan_headers vulkan.hpp grid.glsl)
# The MPI layer installs its folder with its component (src/mpi/CMakeLists.txt).
set(frnn_mpi_headers mpi/collective_error.hpp mpi/communication_plan.hpp mpi/decomposition.hpp
  mpi/distributor.hpp mpi/domain.hpp mpi/halo.hpp)
# A header nobody listed would be missing from installs without anyone noticing: refuse it.
file(GLOB_RECURSE frnn_headers_present RELATIVE ${PROJECT_SOURCE_DIR}/include/frnn
     ${PROJECT_SOURCE_DIR}/include/frnn/*)
foreach(header ${frnn_headers_present})
  if(NOT header IN_LIST frnn_public_headers AND NOT header IN_LIST frnn_vulkan_headers
     AND NOT header IN_LIST frnn_mpi_headers)
    message(FATAL_ERROR "include/frnn/${header} is in no list of cmake/FrnnInstall.cmake")
  endif()
endforeach()
foreach(header ${frnn_public_headers})
  get_filename_component(folder ${header} DIRECTORY)
  install(FILES ${PROJECT_SOURCE_DIR}/include/frnn/${header} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/frnn/${folder})
endforeach()
install(EXPORT frnnTargets NAMESPACE frnn:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/frnn)
export(EXPORT frnnTargets NAMESPACE frnn:: FILE ${PROJECT_BINARY_DIR}/frnnTargets.cmake)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/frnnConfig.cmake.in
  ${PROJECT_BINARY_DIR}/frnnConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/frnn)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/frnnConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/frnnConfig.cmake ${PROJECT_BINARY_DIR}/frnnConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/frnn)
# The licence (MIT) travels with every install; frnnConfig.cmake names it as frnn_LICENSE.
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR})
