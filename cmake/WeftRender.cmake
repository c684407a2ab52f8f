# Finds the tools' picture libraries: stb (PNG writing: the glTF export's texture and the pictures;
# required) and libepoxy (the OpenGL and EGL loader of tools/render's renderer). Sets
# WEFT_HAVE_RENDER when WEFT_RENDER is on and libepoxy is there; without it weft-sim builds without
# --png, --gif and --mp4 and still exports --gltf (ffmpeg is only needed at run time).
option(WEFT_RENDER "Build the renderer (weft-sim --png/--gif/--mp4, the figures) when libepoxy is found" ON)
find_package(PkgConfig REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET GLOBAL stb)
find_package(glm REQUIRED)
set(WEFT_HAVE_RENDER OFF)
if(WEFT_RENDER)
  pkg_check_modules(EPOXY IMPORTED_TARGET GLOBAL epoxy)
  if(EPOXY_FOUND)
    set(WEFT_HAVE_RENDER ON)
  else()
    message(STATUS "weft: renderer off (needs pkg-config epoxy: libepoxy-dev); weft-sim --gltf still works")
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
