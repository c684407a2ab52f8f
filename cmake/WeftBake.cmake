# weft_bake() and weft_bake_all(): bake sewing patterns into .weft assets as part of the build, the
# way a game's asset pipeline would. Each asset is one custom command: Ninja bakes them in
# parallel (every core) and again only when its pattern, a file it names (the body, the manifest)
# or weft-bake itself changed (weft-bake writes a depfile per asset).
#
#   weft_bake(OUTPUT_VAR
#             PATTERNS samples/patterns/skirt.json ...   # Weft or GarmentCode pattern files
#             [DESTINATION dir]                          # default: ${CMAKE_CURRENT_BINARY_DIR}/assets
#             [SUFFIX -dressed]                          # appended to each asset's name
#             [ARGS --target-edge 0.02 ...])             # extra weft-bake arguments (--body mannequin)
#
#   weft_bake_all(OUTPUT_VAR
#                 FOLDER dir | MANIFEST assets.json      # every pattern in a folder, or a manifest
#                 [DESTINATION dir] [ARGS ...])          # (docs/pattern-format.md, "Baking many patterns")
#   add_custom_target(sample_assets ALL DEPENDS ${OUTPUT_VAR})
#
# OUTPUT_VAR receives the list of baked files (DESTINATION/<asset name>.weft). A folder is listed
# again at build time when patterns come or go (CONFIGURE_DEPENDS), a manifest when it changes;
# editing a manifest re-bakes every asset it names. The weft-bake run is the target weft-bake, or
# WEFT_BAKE_EXECUTABLE when set (a project outside Weft's build).

# A pattern file's asset name, as weft-bake names it: without "_specification.json" or ".json".
function(_weft_asset_name output_var pattern)
  get_filename_component(name ${pattern} NAME)
  string(REGEX REPLACE "(_specification)?\\.json$" "" name "${name}")
  set(${output_var} ${name} PARENT_SCOPE)
endfunction()

function(_weft_bake_command output_var)
  if(WEFT_BAKE_EXECUTABLE)
    set(${output_var} ${WEFT_BAKE_EXECUTABLE} PARENT_SCOPE)
  else()
    set(${output_var} weft-bake PARENT_SCOPE)
  endif()
endfunction()

# One asset's custom command: `weft-bake ARGN` writes OUT and its depfile OUT.d; baked again when
# INPUT (the pattern or the manifest), weft-bake or a file the depfile names changed.
function(_weft_bake_asset out name input)
  _weft_bake_command(bake)
  get_filename_component(destination ${out} DIRECTORY)
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${destination}
    COMMAND ${bake} ${ARGN}
    DEPENDS ${bake} ${input}
    DEPFILE ${out}.d
    COMMENT "weft-bake ${name}"
    VERBATIM)
endfunction()

function(weft_bake output_var)
  cmake_parse_arguments(WB "" "DESTINATION;SUFFIX" "PATTERNS;ARGS" ${ARGN})
  if(NOT WB_DESTINATION)
    set(WB_DESTINATION ${CMAKE_CURRENT_BINARY_DIR}/assets)
  endif()
  set(outputs)
  foreach(pattern IN LISTS WB_PATTERNS)
    get_filename_component(pattern_abs ${pattern} ABSOLUTE)
    _weft_asset_name(name ${pattern})
    set(out ${WB_DESTINATION}/${name}${WB_SUFFIX}.weft)
    _weft_bake_asset(${out} ${name}${WB_SUFFIX} ${pattern_abs} ${pattern_abs} -o ${out} --depfile ${out}.d ${WB_ARGS})
    list(APPEND outputs ${out})
  endforeach()
  set(${output_var} ${outputs} PARENT_SCOPE)
endfunction()

function(weft_bake_all output_var)
  cmake_parse_arguments(WB "" "FOLDER;MANIFEST;DESTINATION" "ARGS" ${ARGN})
  if(NOT WB_DESTINATION)
    set(WB_DESTINATION ${CMAKE_CURRENT_BINARY_DIR}/assets)
  endif()
  if(WB_FOLDER AND NOT WB_MANIFEST)
    # weft-bake's folder rule: the GarmentCode specifications when there are any, else every pattern.
    get_filename_component(folder ${WB_FOLDER} ABSOLUTE)
    file(GLOB patterns CONFIGURE_DEPENDS ${folder}/*_specification.json)
    if(NOT patterns)
      file(GLOB patterns CONFIGURE_DEPENDS ${folder}/*.json)
    endif()
    if(NOT patterns)
      message(FATAL_ERROR "weft_bake_all: no pattern (*.json) in ${folder}")
    endif()
    list(SORT patterns)
    weft_bake(outputs PATTERNS ${patterns} DESTINATION ${WB_DESTINATION} ARGS ${WB_ARGS})
    set(${output_var} ${outputs} PARENT_SCOPE)
    return()
  endif()
  if(NOT WB_MANIFEST OR WB_FOLDER)
    message(FATAL_ERROR "weft_bake_all: give FOLDER or MANIFEST, one of them")
  endif()

  # A manifest: one custom command per asset (weft-bake MANIFEST --only NAME), its names read here.
  get_filename_component(manifest ${WB_MANIFEST} ABSOLUTE)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${manifest})
  file(READ ${manifest} text)
  string(JSON count ERROR_VARIABLE error LENGTH "${text}" assets)
  if(error)
    message(FATAL_ERROR "weft_bake_all: ${manifest}: no \"assets\" list (${error})")
  endif()
  set(outputs)
  math(EXPR last "${count} - 1")
  foreach(k RANGE ${last})
    string(JSON name ERROR_VARIABLE no_name GET "${text}" assets ${k} name)
    if(no_name)
      string(JSON pattern ERROR_VARIABLE error GET "${text}" assets ${k} pattern)
      if(error)
        message(FATAL_ERROR "weft_bake_all: ${manifest}: assets[${k}] has no \"pattern\"")
      endif()
      _weft_asset_name(name ${pattern})
    endif()
    set(out ${WB_DESTINATION}/${name}.weft)
    _weft_bake_asset(${out} ${name} ${manifest} ${manifest} -o ${WB_DESTINATION} --only ${name} --depfiles --jobs 1 ${WB_ARGS})
    list(APPEND outputs ${out})
  endforeach()
  set(${output_var} ${outputs} PARENT_SCOPE)
endfunction()
