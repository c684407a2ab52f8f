# weft_bake(): bakes sewing patterns into .weft assets as part of the build, the way a game's asset
# pipeline would. Each asset is one custom command: Ninja bakes them in parallel and again only
# when the pattern, a file it names, or weft-bake itself changed (weft-bake writes a depfile).
#
#   weft_bake(OUTPUT_VAR
#             PATTERNS samples/patterns/skirt.json ...   # Weft or GarmentCode pattern files
#             [DESTINATION dir]                          # default: ${CMAKE_CURRENT_BINARY_DIR}/assets
#             [SUFFIX -dressed]                          # appended to each asset's name
#             [ARGS --target-edge 0.02 ...])             # extra weft-bake arguments (--body mannequin)
#   add_custom_target(sample_assets ALL DEPENDS ${OUTPUT_VAR})
#
# OUTPUT_VAR receives the list of baked files (DESTINATION/<pattern name><SUFFIX>.weft).
function(weft_bake output_var)
  cmake_parse_arguments(WB "" "DESTINATION;SUFFIX" "PATTERNS;ARGS" ${ARGN})
  if(NOT WB_DESTINATION)
    set(WB_DESTINATION ${CMAKE_CURRENT_BINARY_DIR}/assets)
  endif()
  set(outputs)
  foreach(pattern IN LISTS WB_PATTERNS)
    get_filename_component(pattern_abs ${pattern} ABSOLUTE)
    get_filename_component(name ${pattern} NAME_WE)
    set(out ${WB_DESTINATION}/${name}${WB_SUFFIX}.weft)
    add_custom_command(
      OUTPUT ${out}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${WB_DESTINATION}
      COMMAND weft-bake ${pattern_abs} -o ${out} --depfile ${out}.d ${WB_ARGS}
      DEPENDS weft-bake ${pattern_abs}
      DEPFILE ${out}.d
      COMMENT "weft-bake ${name}${WB_SUFFIX}"
      VERBATIM)
    list(APPEND outputs ${out})
  endforeach()
  set(${output_var} ${outputs} PARENT_SCOPE)
endfunction()
