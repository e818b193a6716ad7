# Decides whether the viewer frnn-view is built (FRNN_VIEWER_BUILT). FRNN_BUILD_VIEWER is AUTO
# (the default: built when its packages are found, GLFW 3.3, OpenGL and Dear ImGui through
# pkg-config, which brings its stb dependency), ON (their absence is an error) or OFF. AUTO is
# decided anew at every configure, so installing the packages later is enough.
set(FRNN_BUILD_VIEWER AUTO CACHE STRING "Build the interactive viewer frnn-view: AUTO, ON or OFF (needs libglfw3-dev, libimgui-dev)")
set_property(CACHE FRNN_BUILD_VIEWER PROPERTY STRINGS AUTO ON OFF)
set(FRNN_VIEWER_BUILT OFF)
if(FRNN_BUILD_VIEWER STREQUAL "OFF")
  frnn_part_off(apps/view "FRNN_BUILD_VIEWER=OFF")
  return()
endif()
find_package(glfw3 3.3 QUIET)
find_package(OpenGL QUIET COMPONENTS OpenGL)
find_package(PkgConfig QUIET)
if(PKG_CONFIG_FOUND)
  pkg_check_modules(FRNN_IMGUI QUIET IMPORTED_TARGET imgui)
endif()
set(frnn_viewer_missing "needs libglfw3-dev, libimgui-dev, pkg-config; glfw3: ${glfw3_FOUND}, "
                        "OpenGL: ${OpenGL_FOUND}, imgui: ${FRNN_IMGUI_FOUND}")
string(CONCAT frnn_viewer_missing ${frnn_viewer_missing})
if(glfw3_FOUND AND OpenGL_FOUND AND FRNN_IMGUI_FOUND)
  set(FRNN_VIEWER_BUILT ON)
elseif(FRNN_BUILD_VIEWER STREQUAL "AUTO")
  frnn_part_missing(apps/view "${frnn_viewer_missing}")
else()
  message(FATAL_ERROR "FRNN_BUILD_VIEWER is ${FRNN_BUILD_VIEWER} but its packages are missing (${frnn_viewer_missing})")
endif()
