# GLSL sources live as files under src/, beside the code that uses them; at build time they are
# checked with glslangValidator (after expanding our #include lines) and embedded into the target
# that owns them, so headless runs need no files beside the binary. Names are paths relative to
# src/. Each target embeds only its own folder's shaders (the GPU layer knows no representation):
#   standin_embed_shaders(TARGET DIRECTORY dir [dir...] [HEADERS file...])
# writes embedded_shaders.inc into a directory on TARGET's private include path; one .cpp of the
# target that is always linked includes it, and its static registration hands the sources to
# gpu::register_embedded_shaders.
function(standin_embed_shaders target)
  cmake_parse_arguments(ARG "" "" "DIRECTORY;HEADERS" ${ARGN})
  set(shader_files "")
  foreach(dir ${ARG_DIRECTORY})
    file(GLOB_RECURSE found CONFIGURE_DEPENDS
      ${PROJECT_SOURCE_DIR}/src/${dir}/*.glsl ${PROJECT_SOURCE_DIR}/src/${dir}/*.vert
      ${PROJECT_SOURCE_DIR}/src/${dir}/*.frag ${PROJECT_SOURCE_DIR}/src/${dir}/*.comp
      ${PROJECT_SOURCE_DIR}/src/${dir}/*.geom ${PROJECT_SOURCE_DIR}/src/${dir}/*.tesc
      ${PROJECT_SOURCE_DIR}/src/${dir}/*.tese)
    list(APPEND shader_files ${found})
  endforeach()
  foreach(header ${ARG_HEADERS})
    list(APPEND shader_files ${PROJECT_SOURCE_DIR}/src/${header})
  endforeach()
  list(SORT shader_files)
  # every shader this target's stages may include, for the dependency list
  file(GLOB_RECURSE includable CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/*.glsl ${PROJECT_SOURCE_DIR}/src/gpu/shaders/common/*.h)
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/${target}_shaders)
  set(out ${out_dir}/embedded_shaders.inc)
  string(REPLACE ";" "|" shader_list "${shader_files}")
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DSRC_ROOT=${PROJECT_SOURCE_DIR}/src -DOUT=${out}
            -DFILES=${shader_list} -DVALIDATOR=${GLSLANG_VALIDATOR}
            -DWORK=${out_dir}/check
            -P ${PROJECT_SOURCE_DIR}/cmake/embed_shaders.cmake
    DEPENDS ${shader_files} ${includable} ${PROJECT_SOURCE_DIR}/cmake/embed_shaders.cmake
    COMMENT "Checking and embedding the GLSL shaders of ${target}"
    VERBATIM)
  target_sources(${target} PRIVATE ${out})
  target_include_directories(${target} PRIVATE ${out_dir})
endfunction()

# standin_standalone_glsl(FOLDER): FOLDER's run-time shaders flattened into one self-contained,
# documented GLSL file (cmake/standalone_glsl.cmake), the reference for porting them to another
# engine: build/share/standin/glsl/NAME.glsl, checked by glslangValidator, built with `all` and
# installed to share/standin/glsl/. Called per representation by standin_representation.
function(standin_standalone_glsl folder)
  get_filename_component(name ${folder} NAME)
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${folder}/shaders/*)
  file(GLOB_RECURSE includable CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/*.glsl ${PROJECT_SOURCE_DIR}/src/*/shaders/*.h)
  set(out ${PROJECT_BINARY_DIR}/share/standin/glsl/${name}.glsl)
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DSRC_ROOT=${PROJECT_SOURCE_DIR}/src -DFOLDER=${folder} -DOUT=${out}
            -DVALIDATOR=${GLSLANG_VALIDATOR} -P ${PROJECT_SOURCE_DIR}/cmake/standalone_glsl.cmake
    DEPENDS ${sources} ${includable} ${PROJECT_SOURCE_DIR}/cmake/standalone_glsl.cmake
    COMMENT "Flattening the shaders of ${folder} into share/standin/glsl/${name}.glsl"
    VERBATIM)
  add_custom_target(standin_glsl_${name} ALL DEPENDS ${out})
  install(FILES ${out} DESTINATION ${CMAKE_INSTALL_DATADIR}/standin/glsl)
endfunction()
