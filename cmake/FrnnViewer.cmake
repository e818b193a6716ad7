# Decides FRNN_BUILD_VIEWER: on by default when the viewer's packages are found (GLFW 3.3,
# OpenGL, Dear ImGui through pkg-config, which brings its stb dependency), otherwise off with a
# STATUS line naming the packages. Forcing it on without them is an error.
find_package(glfw3 3.3 QUIET)
find_package(OpenGL QUIET COMPONENTS OpenGL)
find_package(PkgConfig QUIET)
if(PKG_CONFIG_FOUND)
  pkg_check_modules(FRNN_IMGUI QUIET IMPORTED_TARGET imgui)
endif()
if(glfw3_FOUND AND OpenGL_FOUND AND FRNN_IMGUI_FOUND)
  set(frnn_viewer_found ON)
else()
  set(frnn_viewer_found OFF)
endif()
option(FRNN_BUILD_VIEWER "Build the interactive viewer frnn-view (needs libglfw3-dev, libimgui-dev)" ${frnn_viewer_found})
if(FRNN_BUILD_VIEWER AND NOT frnn_viewer_found)
  message(FATAL_ERROR "FRNN_BUILD_VIEWER is on but its packages are missing (needs libglfw3-dev, libimgui-dev, pkg-config; "
                      "glfw3: ${glfw3_FOUND}, OpenGL: ${OpenGL_FOUND}, imgui: ${FRNN_IMGUI_FOUND})")
elseif(NOT FRNN_BUILD_VIEWER)
  message(STATUS "frnn: viewer disabled (needs libglfw3-dev, libimgui-dev; glfw3: ${glfw3_FOUND}, "
                 "OpenGL: ${OpenGL_FOUND}, imgui: ${FRNN_IMGUI_FOUND})")
endif()
