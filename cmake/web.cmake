# The browser build (Emscripten; tools/web-build.sh runs `emcmake cmake -S . -B build-web`): the
# portable modules (cmake/modules.cmake) and the browser entry (apps/web/), linked into
# dist/histoview_web.js + .wasm. Header-only dependencies come from the Debian packages; the
# system include directory itself must not be searched (its C library headers are glibc's), so
# a directory of links to just those libraries stands in for it.
set(HV_WEB_INCLUDE ${CMAKE_BINARY_DIR}/include-system)
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

# -O2: the optimisation level found working with Debian's emcc 3.1.6 (with -sMINIFY_HTML=0);
# exceptions on, since bad input is reported by exceptions.
set(HV_WEB_FLAGS -O2 -fexceptions)
add_compile_options(${HV_WEB_FLAGS})

# The third-party names of the module table: header-only libraries, stb (compiled once in
# apps/web/stb_impl.cpp) and WebGL2 (Emscripten's GLES 3 headers).
function(hv_external name)
  add_library(hv_ext_${name} INTERFACE)
  target_include_directories(hv_ext_${name} INTERFACE ${ARGN})
endfunction()
hv_external(threads)
hv_external(glm ${HV_WEB_INCLUDE})
target_compile_definitions(hv_ext_glm INTERFACE GLM_FORCE_CXX17 GLM_ENABLE_EXPERIMENTAL)
hv_external(json ${HV_WEB_INCLUDE})
hv_external(eigen /usr/include/eigen3)
hv_external(nanoflann ${HV_WEB_INCLUDE})
hv_external(stb /usr/include/stb)
hv_external(gles)

hv_embed_shaders(HV_SHADER_CPP)
hv_define_modules()
get_property(HV_MODULES GLOBAL PROPERTY HV_MODULES)

add_executable(histoview_web ${CMAKE_SOURCE_DIR}/apps/web/hv_web.cpp ${CMAKE_SOURCE_DIR}/apps/web/web_services.cpp ${CMAKE_SOURCE_DIR}/apps/web/hv_web_tiles.cpp
               ${CMAKE_SOURCE_DIR}/apps/web/hv_web_frame.cpp
               ${CMAKE_SOURCE_DIR}/apps/web/stb_impl.cpp)
target_compile_options(histoview_web PRIVATE ${HV_WARNINGS})
target_link_libraries(histoview_web PRIVATE hv_ext_stb)
foreach(m ${HV_MODULES})
  target_link_libraries(histoview_web PRIVATE hv_${m})
endforeach()
target_link_options(histoview_web PRIVATE ${HV_WEB_FLAGS}
  --bind
  -sMIN_WEBGL_VERSION=2 -sMAX_WEBGL_VERSION=2
  -sALLOW_MEMORY_GROWTH=1 -sMAXIMUM_MEMORY=2GB
  -sMODULARIZE=1 -sEXPORT_NAME=createHistoview
  -sEXPORTED_RUNTIME_METHODS=FS
  -sENVIRONMENT=web
  -sMINIFY_HTML=0)
set_target_properties(histoview_web PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/dist SUFFIX ".js")
