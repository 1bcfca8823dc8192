# The Debian packages standin's libraries use, as imported targets. Included by the build and, once
# installed, by standinConfig.cmake: a program linking the static libraries needs the same ones.
find_package(PkgConfig REQUIRED)
find_package(glm REQUIRED)
find_package(assimp REQUIRED)
find_package(embree 3 REQUIRED)
find_package(meshoptimizer REQUIRED)
find_package(TBB REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
# zlib (Debian zlib1g-dev, already needed by libpng): supercompression of KTX2 package images
find_package(ZLIB REQUIRED)
foreach(module EPOXY:epoxy EGL:egl STB:stb PNG:libpng LCMS2:lcms2)
  string(REPLACE ":" ";" pair ${module})
  list(GET pair 0 prefix)
  list(GET pair 1 name)
  if(NOT TARGET PkgConfig::${prefix})
    pkg_check_modules(${prefix} REQUIRED IMPORTED_TARGET ${name})
  endif()
endforeach()
# libsquish (DXT compression of view-atlas pages): Debian's libsquish.pc has an empty prefix, so
# its include path reads "/include"; find the header and library directly instead.
if(NOT TARGET squish::squish)
  find_path(SQUISH_INCLUDE_DIR squish.h REQUIRED)
  find_library(SQUISH_LIBRARY squish REQUIRED)
  add_library(squish::squish UNKNOWN IMPORTED)
  set_target_properties(squish::squish PROPERTIES IMPORTED_LOCATION "${SQUISH_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${SQUISH_INCLUDE_DIR}")
endif()
