# GLSL sources live as files under src/; at build time they are checked with glslangValidator
# (after expanding our #include lines) and embedded into the library as string literals, so that
# headless runs need no files beside the binary. Names are paths relative to src/.
function(standin_embed_shaders target)
  file(GLOB_RECURSE shader_files CONFIGURE_DEPENDS
    ${PROJECT_SOURCE_DIR}/src/*.glsl ${PROJECT_SOURCE_DIR}/src/*.vert ${PROJECT_SOURCE_DIR}/src/*.frag
    ${PROJECT_SOURCE_DIR}/src/*.comp ${PROJECT_SOURCE_DIR}/src/*.geom
    ${PROJECT_SOURCE_DIR}/src/*.tesc ${PROJECT_SOURCE_DIR}/src/*.tese
    ${PROJECT_SOURCE_DIR}/src/gpu/shaders/common/*.h)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded_shaders.cpp)
  string(REPLACE ";" "|" shader_list "${shader_files}")
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DSRC_ROOT=${PROJECT_SOURCE_DIR}/src -DOUT=${out}
            -DFILES=${shader_list} -DVALIDATOR=${GLSLANG_VALIDATOR}
            -DWORK=${CMAKE_CURRENT_BINARY_DIR}/shader_check
            -P ${PROJECT_SOURCE_DIR}/cmake/embed_shaders.cmake
    DEPENDS ${shader_files} ${PROJECT_SOURCE_DIR}/cmake/embed_shaders.cmake
    COMMENT "Checking and embedding GLSL shaders"
    VERBATIM)
  target_sources(${target} PRIVATE ${out})
endfunction()
