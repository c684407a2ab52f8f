# Installs Khronos' glTF validator (npm package gltf-validator, pinned) into PREFIX with the
# machine's npm, once: a later run finds it there and does nothing. Run by CTest as the fixture
# setup of the glTF tests:   cmake -DNPM=... -DPREFIX=... -P install-validator.cmake
set(version 2.0.0-dev.3.10)
if(EXISTS ${PREFIX}/node_modules/gltf-validator/package.json)
  file(READ ${PREFIX}/node_modules/gltf-validator/package.json package)
  if(package MATCHES "\"version\": *\"${version}\"")
    message(STATUS "gltf-validator ${version} already in ${PREFIX}")
    return()
  endif()
endif()
file(MAKE_DIRECTORY ${PREFIX})
execute_process(COMMAND ${NPM} install --prefix ${PREFIX} --no-audit --no-fund --no-save gltf-validator@${version}
                RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "npm install gltf-validator@${version} failed (${result}): is the npm registry reachable?")
endif()
