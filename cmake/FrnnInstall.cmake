# Install rules and the package config that makes find_package(frnn) work.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)
install(TARGETS frnn EXPORT frnnTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/frnn DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT frnnTargets NAMESPACE frnn:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/frnn)
export(EXPORT frnnTargets NAMESPACE frnn:: FILE ${PROJECT_BINARY_DIR}/frnnTargets.cmake)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/frnnConfig.cmake.in
  ${PROJECT_BINARY_DIR}/frnnConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/frnn)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/frnnConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/frnnConfig.cmake ${PROJECT_BINARY_DIR}/frnnConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/frnn)
