# Finds the renderer's libraries (tools/render): libepoxy (OpenGL and EGL loader) and stb
# (PNG writing). Sets WEFT_HAVE_RENDER when WEFT_RENDER is on and both are there; without them
# weft-sim builds without --png, --gif and --mp4 (ffmpeg is only needed at run time).
option(WEFT_RENDER "Build the renderer (weft-sim --png/--gif/--mp4, the figures) when its libraries are found" ON)
set(WEFT_HAVE_RENDER OFF)
if(WEFT_RENDER)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(EPOXY IMPORTED_TARGET GLOBAL epoxy)
  pkg_check_modules(STB IMPORTED_TARGET GLOBAL stb)
  find_package(glm REQUIRED)
  if(EPOXY_FOUND AND STB_FOUND)
    set(WEFT_HAVE_RENDER ON)
  else()
    message(STATUS "weft: renderer off (needs pkg-config epoxy and stb: libepoxy-dev, libstb-dev)")
  endif()
endif()

# The interactive viewer (samples/viewer) also needs a window and a panel: GLFW and Dear ImGui
# (libglfw3-dev, libimgui-dev). Sets WEFT_HAVE_VIEWER.
if(WEFT_HAVE_RENDER)
  pkg_check_modules(GLFW IMPORTED_TARGET GLOBAL glfw3)
  pkg_check_modules(IMGUI IMPORTED_TARGET GLOBAL imgui)
endif()
set(WEFT_HAVE_VIEWER ${WEFT_HAVE_RENDER})
if(WEFT_HAVE_RENDER AND NOT (GLFW_FOUND AND IMGUI_FOUND))
  set(WEFT_HAVE_VIEWER OFF)
  message(STATUS "weft: viewer off (needs pkg-config glfw3 and imgui: libglfw3-dev, libimgui-dev)")
endif()
