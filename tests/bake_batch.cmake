# weft-bake's batches from the command line, run by CTest as `cmake -P` scripts (tests/CMakeLists.txt):
#
#   -DCHECK=jobs         a folder baked at --jobs 1 and at --jobs 2 writes the same bytes
#   -DCHECK=broken       a folder with broken patterns: each fails alone, the others are baked, exit 1
#   -DCHECK=warnings     a batch names on stderr what it repaired in a pattern, as one pattern's bake
#                        does (a shared corpus garment whose curve overshoots its corner)
#   -DCHECK=incremental  a project using weft_bake_all (FOLDER and MANIFEST): built, built again
#                        (nothing to do), one pattern touched: only its assets are baked again
#
# Inputs: WEFT_BAKE (the executable), SOURCE_DIR (the repository), WORK_DIR (emptied first), for
# `incremental` MAKE_PROGRAM (ninja), for `warnings` SHARED_DATA_DIR (../shared/data).
cmake_minimum_required(VERSION 3.20)

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(bake_folder folder out jobs result_var stderr_var)
  execute_process(COMMAND ${WEFT_BAKE} ${folder} -o ${out} --jobs ${jobs}
                  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE error)
  message(STATUS "weft-bake ${folder} --jobs ${jobs}: exit ${result}\n${output}${error}")
  set(${result_var} ${result} PARENT_SCOPE)
  set(${stderr_var} "${error}" PARENT_SCOPE)
endfunction()

if(CHECK STREQUAL "jobs")
  set(folder ${SOURCE_DIR}/samples/patterns)
  bake_folder(${folder} ${WORK_DIR}/one 1 result error)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "--jobs 1 failed")
  endif()
  bake_folder(${folder} ${WORK_DIR}/two 2 result error)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "--jobs 2 failed")
  endif()
  file(GLOB patterns ${folder}/*.json)
  foreach(pattern IN LISTS patterns)
    get_filename_component(name ${pattern} NAME_WE)
    if(NOT EXISTS ${WORK_DIR}/one/${name}.weft)
      message(FATAL_ERROR "no ${name}.weft")
    endif()
    file(SHA256 ${WORK_DIR}/one/${name}.weft one)
    file(SHA256 ${WORK_DIR}/two/${name}.weft two)
    if(NOT one STREQUAL two)
      message(FATAL_ERROR "${name}.weft differs between --jobs 1 and --jobs 2")
    endif()
  endforeach()

elseif(CHECK STREQUAL "warnings")
  set(pattern ${SHARED_DATA_DIR}/patterns/garmentcode-sampled/gc_1001_0080_specification.json)
  file(COPY ${pattern} DESTINATION ${WORK_DIR}/in)
  execute_process(COMMAND ${WEFT_BAKE} ${pattern} -o ${WORK_DIR}/one.weft
                  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE one)
  if(NOT result EQUAL 0 OR NOT one MATCHES "gc_1001_0080_specification.json: repaired: panel ")
    message(FATAL_ERROR "one pattern: exit ${result}, no repair on stderr:\n${one}")
  endif()
  bake_folder(${WORK_DIR}/in ${WORK_DIR}/out 1 result error)
  if(NOT result EQUAL 0 OR NOT error MATCHES "weft-bake: gc_1001_0080: repaired: panel ")
    message(FATAL_ERROR "a batch: exit ${result}, no repair on stderr")
  endif()
  string(REGEX MATCHALL "repaired: [^\n]*" one_repairs "${one}")
  string(REGEX MATCHALL "repaired: [^\n]*" batch_repairs "${error}")
  if(NOT one_repairs STREQUAL batch_repairs)
    message(FATAL_ERROR "a batch reports other repairs than one pattern's bake:\n${one_repairs}\n${batch_repairs}")
  endif()

elseif(CHECK STREQUAL "broken")
  # The pattern fuzzer's seeds: the broken_ patterns among good ones.
  set(folder ${SOURCE_DIR}/tests/fuzz/corpus/pattern)
  bake_folder(${folder} ${WORK_DIR}/out 2 result error)
  if(result EQUAL 0)
    message(FATAL_ERROR "exit status 0 with broken patterns")
  endif()
  file(GLOB patterns RELATIVE ${folder} ${folder}/*.json)
  foreach(pattern IN LISTS patterns)
    string(REGEX REPLACE "\\.json$" "" name ${pattern})
    if(name MATCHES "^broken_")
      if(EXISTS ${WORK_DIR}/out/${name}.weft OR NOT error MATCHES "weft-bake: ${name} failed: [^\n]*${pattern}: ")
        message(FATAL_ERROR "${name}: not refused with its own error")
      endif()
    elseif(NOT EXISTS ${WORK_DIR}/out/${name}.weft)
      message(FATAL_ERROR "${name}: not baked beside the broken patterns")
    endif()
  endforeach()

elseif(CHECK STREQUAL "incremental")
  set(project ${WORK_DIR}/project)
  file(MAKE_DIRECTORY ${project}/patterns)
  foreach(name flag sheet)
    configure_file(${SOURCE_DIR}/samples/patterns/${name}.json ${project}/patterns/${name}.json COPYONLY)
  endforeach()
  file(WRITE ${project}/assets.json [=[{
  "format": "weft-bake-manifest",
  "defaults": { "target_edge_m": 0.05 },
  "assets": [
    { "pattern": "patterns/flag.json", "name": "coarse-flag" },
    { "pattern": "patterns/sheet.json" }
  ]
}
]=])
  file(WRITE ${project}/CMakeLists.txt "cmake_minimum_required(VERSION 3.20)
project(baked NONE)
set(WEFT_BAKE_EXECUTABLE ${WEFT_BAKE})
include(${SOURCE_DIR}/cmake/WeftBake.cmake)
weft_bake_all(FOLDER_ASSETS FOLDER patterns DESTINATION \${CMAKE_BINARY_DIR}/folder)
weft_bake_all(MANIFEST_ASSETS MANIFEST assets.json DESTINATION \${CMAKE_BINARY_DIR}/manifest)
add_custom_target(assets ALL DEPENDS \${FOLDER_ASSETS} \${MANIFEST_ASSETS})
")
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${project} -B ${project}/build -G Ninja -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}
                  RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "configuring the project failed")
  endif()
  # build(EXPECTED...): builds and checks which assets were baked, by the commands' comments.
  function(build)
    execute_process(COMMAND ${MAKE_PROGRAM} -C ${project}/build RESULT_VARIABLE result OUTPUT_VARIABLE output)
    message(STATUS "${output}")
    if(NOT result EQUAL 0)
      message(FATAL_ERROR "building the project failed")
    endif()
    string(REGEX MATCHALL "weft-bake [a-z-]+" baked "${output}")
    list(SORT baked)
    set(expected ${ARGN})
    list(SORT expected)
    if(NOT "${baked}" STREQUAL "${expected}")
      message(FATAL_ERROR "baked '${baked}', expected '${expected}'")
    endif()
  endfunction()
  build("weft-bake flag" "weft-bake sheet" "weft-bake coarse-flag" "weft-bake sheet")
  foreach(asset folder/flag folder/sheet manifest/coarse-flag manifest/sheet)
    if(NOT EXISTS ${project}/build/${asset}.weft)
      message(FATAL_ERROR "no ${asset}.weft")
    endif()
  endforeach()
  build()
  # The manifest's assets depend on the manifest and their pattern (and body, when sewn).
  file(READ ${project}/build/manifest/coarse-flag.weft.d depfile)
  if(NOT depfile MATCHES "coarse-flag.weft: [^\n]*patterns/flag.json [^\n]*assets.json")
    message(FATAL_ERROR "coarse-flag.weft.d does not name the pattern and the manifest: ${depfile}")
  endif()
  file(TOUCH ${project}/patterns/flag.json)
  build("weft-bake flag" "weft-bake coarse-flag")
  build()
else()
  message(FATAL_ERROR "CHECK=${CHECK}: not jobs, broken or incremental")
endif()
