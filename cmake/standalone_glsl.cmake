# cmake -P script: one self-contained GLSL file per representation, the reference for porting its
# run-time shaders to another engine. It is generated from the shaders the renderer really runs, so
# it cannot drift from them:
#   - every stage file of src/FOLDER/shaders/ (.vert .frag .comp .geom .tesc .tese) is flattened:
#     each `#include "..."` is replaced by the file it names (once per stage, like #pragma once),
#     between "begin"/"end" marker comments that name the source file;
#   - the stages' common `#version` line is written once at the top and each stage is wrapped in
#     `#if defined(STANDIN_<FILE>_<EXT>)`, so one file holds them all: define one macro, compile;
#   - the header comment is the folder's hand-written shaders/PORTING.md (the conventions a porter
#     needs and no declaration says: spaces, encodings, which stages make a program, what the host
#     computes), then, per stage, its interface as declared (uniforms, blocks, inputs, outputs,
#     samplers), extracted from the flattened text;
#   - every stage is checked with glslangValidator (-l -S STAGE -DSTANDIN_<FILE>_<EXT>), and the
#     result must contain no #include.
cmake_minimum_required(VERSION 3.25)
# Variables: SRC_ROOT (src/), FOLDER (e.g. reps/view_atlas), OUT (the .glsl to write), VALIDATOR.

get_filename_component(name ${FOLDER} NAME)
set(shader_dir ${SRC_ROOT}/${FOLDER}/shaders)
file(GLOB stages RELATIVE ${shader_dir}
  ${shader_dir}/*.vert ${shader_dir}/*.tesc ${shader_dir}/*.tese ${shader_dir}/*.geom
  ${shader_dir}/*.frag ${shader_dir}/*.comp)
list(SORT stages)
if(NOT stages)
  message(FATAL_ERROR "${FOLDER}/shaders: no shader stages to flatten")
endif()

# text of PATH with its includes expanded; GLOBAL property standin_flat_seen lists what this stage
# has already pulled in
function(flatten path depth result)
  if(depth GREATER 16)
    message(FATAL_ERROR "shader include depth exceeded at ${path}")
  endif()
  file(READ ${path} text)
  string(REGEX MATCHALL "#include \"[^\"]+\"" includes "${text}")
  list(REMOVE_DUPLICATES includes)
  foreach(inc ${includes})
    string(REGEX REPLACE "#include \"([^\"]+)\"" "\\1" inc_name "${inc}")
    if(NOT EXISTS ${SRC_ROOT}/${inc_name})
      message(FATAL_ERROR "${path}: included file ${inc_name} not found under src/")
    endif()
    get_property(seen GLOBAL PROPERTY standin_flat_seen)
    if(inc_name IN_LIST seen)
      set(inc_text "// (src/${inc_name}: included above)")
    else()
      set_property(GLOBAL APPEND PROPERTY standin_flat_seen ${inc_name})
      math(EXPR next "${depth} + 1")
      flatten(${SRC_ROOT}/${inc_name} ${next} body)
      string(REGEX REPLACE "\n+$" "" body "${body}")
      set(inc_text "// ---- begin src/${inc_name} ----\n${body}\n// ---- end src/${inc_name} ----")
    endif()
    string(REPLACE "${inc}" "${inc_text}" text "${text}")
  endforeach()
  set(${result} "${text}" PARENT_SCOPE)
endfunction()

set(version "")
set(blocks "")
set(stage_list "")
set(interfaces "")
foreach(stage_file ${stages})
  set_property(GLOBAL PROPERTY standin_flat_seen "")
  flatten(${shader_dir}/${stage_file} 0 text)
  string(REGEX MATCH "^#version [^\n]*" stage_version "${text}")
  if(NOT stage_version)
    message(FATAL_ERROR "${FOLDER}/shaders/${stage_file}: does not open with #version")
  endif()
  if(version AND NOT version STREQUAL stage_version)
    message(FATAL_ERROR "${FOLDER}/shaders/${stage_file}: ${stage_version} differs from the other stages' ${version}")
  endif()
  set(version "${stage_version}")
  string(REGEX REPLACE "^#version [^\n]*\n" "" text "${text}")
  string(REGEX REPLACE "\n+$" "" text "${text}")
  string(REPLACE "." "_" macro "${stage_file}")
  string(TOUPPER "STANDIN_${macro}" macro)
  string(REGEX MATCH "[a-z]+$" ext "${stage_file}")
  string(APPEND stage_list "//   ${macro}  (-S ${ext})  from src/${FOLDER}/shaders/${stage_file}\n")
  string(APPEND blocks "\n#if defined(${macro}) // ======== src/${FOLDER}/shaders/${stage_file} ========\n${text}\n#endif // ${macro}\n")

  # the declared interface: global uniforms, blocks, stage inputs and outputs (';' would split lists)
  string(REPLACE ";" "<semicolon>" scan "\n${text}")
  string(REGEX MATCHALL "\n(layout\\([^)]*\\) *)?((flat|noperspective|patch) +)?(uniform|in|out|buffer|readonly buffer|writeonly buffer|coherent buffer|shared) [^\n]*" declared "${scan}")
  string(APPEND interfaces "//   ${macro}:\n")
  foreach(line ${declared})
    string(REGEX REPLACE "^\n" "" line "${line}")
    string(REPLACE "<semicolon>" ";" line "${line}")
    string(APPEND interfaces "//     ${line}\n")
  endforeach()
  list(APPEND stage_files ${stage_file})
endforeach()

set(porting "")
if(EXISTS ${shader_dir}/PORTING.md)
  file(STRINGS ${shader_dir}/PORTING.md doc_lines)
  foreach(line ${doc_lines})
    if(line STREQUAL "")
      string(APPEND porting "//\n")
    else()
      string(APPEND porting "// ${line}\n")
    endif()
  endforeach()
else()
  message(FATAL_ERROR "${FOLDER}/shaders/PORTING.md is missing: it documents the conventions of the standalone GLSL")
endif()

set(out_text "// ${name}.glsl: the run-time shaders of standin's ${name} representation in one self-contained file.
// Generated by cmake/standalone_glsl.cmake from src/${FOLDER}/shaders/ (the shaders the renderer runs,
// their #includes flattened); do not edit: edit those, and shaders/PORTING.md for this header.
//
${porting}//
// ---- Stages ----
// Each stage of the renderer is one #if block below. Compile a stage by defining its macro after the
// #version line (glslangValidator -l -S STAGE -DMACRO ${name}.glsl checks it), e.g.
${stage_list}//
// ---- Interface per stage (extracted from the declarations below) ----
${interfaces}
${version}
${blocks}")
string(REPLACE "\r" "" out_text "${out_text}")
if(out_text MATCHES "\n[ \t]*#include ")
  message(FATAL_ERROR "${OUT}: an #include survived flattening")
endif()

get_filename_component(out_dir ${OUT} DIRECTORY)
file(MAKE_DIRECTORY ${out_dir})
file(WRITE ${OUT}.tmp "${out_text}")
foreach(stage_file ${stage_files})
  string(REPLACE "." "_" macro "${stage_file}")
  string(TOUPPER "STANDIN_${macro}" macro)
  string(REGEX MATCH "[a-z]+$" ext "${stage_file}")
  execute_process(COMMAND ${VALIDATOR} -l -S ${ext} -D${macro} ${OUT}.tmp
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    file(REMOVE ${OUT}.tmp)
    message(FATAL_ERROR "glslangValidator rejected ${name}.glsl with ${macro}:\n${out}${err}")
  endif()
endforeach()
file(RENAME ${OUT}.tmp ${OUT})
