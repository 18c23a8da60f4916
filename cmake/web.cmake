# The browser build (Emscripten; tools/web-build.sh runs `emcmake cmake -S . -B build-web`): the
# portable core (cmake/portable_sources.cmake) and the web entry (web/hv_web.cpp), linked into
# dist/histoview_web.js + .wasm. Header-only dependencies come from the Debian packages; the
# system include directory itself must not be searched (its C library headers are glibc's), so
# a directory of links to just those libraries stands in for it.
set(HV_WEB_INCLUDE ${CMAKE_BINARY_DIR}/include)
file(MAKE_DIRECTORY ${HV_WEB_INCLUDE})
foreach(lib glm nlohmann nanoflann.hpp)
  if(NOT EXISTS /usr/include/${lib})
    message(FATAL_ERROR "/usr/include/${lib} not found: install libglm-dev, nlohmann-json3-dev and libnanoflann-dev")
  endif()
  file(CREATE_LINK /usr/include/${lib} ${HV_WEB_INCLUDE}/${lib} SYMBOLIC)
endforeach()
foreach(dir /usr/include/eigen3 /usr/include/stb)
  if(NOT EXISTS ${dir})
    message(FATAL_ERROR "${dir} not found: install libeigen3-dev and libstb-dev")
  endif()
endforeach()

hv_portable_sources(HV_PORTABLE_SOURCES)
hv_embed_shaders(HV_SHADER_CPP)

# -O2: the optimisation level PLATFORM notes found working with Debian's emcc 3.1.6 (with
# -sMINIFY_HTML=0); exceptions on, since bad input is reported by exceptions.
set(HV_WEB_FLAGS -O2 -fexceptions)
add_library(hvportable STATIC ${HV_PORTABLE_SOURCES} ${HV_SHADER_CPP} ${CMAKE_SOURCE_DIR}/web/stb_impl.cpp)
target_include_directories(hvportable PUBLIC ${CMAKE_SOURCE_DIR}/src ${HV_WEB_INCLUDE} /usr/include/eigen3
                                             /usr/include/stb)
target_compile_definitions(hvportable PUBLIC GLM_FORCE_CXX17 GLM_ENABLE_EXPERIMENTAL)
target_compile_options(hvportable PUBLIC ${HV_WEB_FLAGS} PRIVATE -Wall -Wextra -Wno-missing-field-initializers)

add_executable(histoview_web ${CMAKE_SOURCE_DIR}/web/hv_web.cpp)
target_link_libraries(histoview_web PRIVATE hvportable)
target_link_options(histoview_web PRIVATE ${HV_WEB_FLAGS}
  --bind
  -sMIN_WEBGL_VERSION=2 -sMAX_WEBGL_VERSION=2
  -sALLOW_MEMORY_GROWTH=1 -sMAXIMUM_MEMORY=2GB
  -sMODULARIZE=1 -sEXPORT_NAME=createHistoview
  -sEXPORTED_RUNTIME_METHODS=FS
  -sENVIRONMENT=web
  -sMINIFY_HTML=0)
set_target_properties(histoview_web PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/dist SUFFIX ".js")
