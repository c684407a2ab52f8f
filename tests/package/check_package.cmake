# The installable package end to end (cmake -P): installs BUILD_DIR into a fresh prefix, configures
# the out-of-tree consumer (tests/package/consumer) against it with find_package(Weft), builds it
# and runs it (with ASSET, a baked .weft, when given) and the C++ cooker (Weft::cook): each must
# print OK.
#   cmake -DBUILD_DIR=... -DCONSUMER_DIR=... -DWORK_DIR=... -DGENERATOR=... [-DMAKE_PROGRAM=...]
#         [-DC_COMPILER=... -DCXX_COMPILER=...] [-DASSET=...] -P check_package.cmake
foreach(var BUILD_DIR CONSUMER_DIR WORK_DIR GENERATOR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_package.cmake: ${var} is not set")
  endif()
endforeach()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    string(REPLACE ";" " " command "${ARGN}")
    message(FATAL_ERROR "failed (${code}): ${command}\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
set(consumer_build ${WORK_DIR}/consumer-build)
file(REMOVE_RECURSE ${WORK_DIR})
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(file include/weft/weft_c.h include/weft/world.h include/weft/cook.h lib/libweft.a lib/libweft_cook.a
             lib/cmake/Weft/WeftConfig.cmake
             lib/cmake/Weft/WeftConfigVersion.cmake lib/cmake/Weft/WeftTargets.cmake)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "the install did not write ${file}")
  endif()
endforeach()

set(configure ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${consumer_build} -G ${GENERATOR} -DCMAKE_PREFIX_PATH=${prefix})
if(MAKE_PROGRAM)
  list(APPEND configure -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM})
endif()
if(C_COMPILER)
  list(APPEND configure -DCMAKE_C_COMPILER=${C_COMPILER})
endif()
if(CXX_COMPILER)
  list(APPEND configure -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
endif()
run(${configure})
run(${CMAKE_COMMAND} --build ${consumer_build})
run(${consumer_build}/consumer ${ASSET})
if(NOT run_output MATCHES "^OK\n$")
  message(FATAL_ERROR "the consumer printed '${run_output}', not OK")
endif()
run(${consumer_build}/cooker)
if(NOT run_output MATCHES "^OK\n$")
  message(FATAL_ERROR "the cooker printed '${run_output}', not OK")
endif()
message(STATUS "installed into ${prefix}; the consumer and the cooker built against it and printed OK")
