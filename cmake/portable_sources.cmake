# The portable core: the sources that build for the browser (Emscripten, WebGL2) as well as
# natively, with no GDAL, GEOS, Embree, Assimp, libpng or EGL. Everything else under src/hv is
# native. The rule: a source is portable when its directory is listed in HV_PORTABLE_DIRS or the
# file itself in HV_PORTABLE_FILES; a new file anywhere else (a reader under io/, points/, ...)
# is native by default. Native libraries are reached from portable code only through small
# interfaces (hv/scene/ray_query.h, hv/gpu/context.h); tests/portable_link_check.cpp links the
# whole portable library without them (docs/web.md).
set(HV_PORTABLE_DIRS camera ibr points render render/gl util)
set(HV_PORTABLE_FILES
  gpu/gl.cpp gpu/present.cpp
  image/image_io.cpp image/colormap.cpp
  scene/mesh.cpp scene/scene.cpp
  io/cameras_json.cpp io/camera_path_json.cpp io/web_scene.cpp
  viewer/navigation.cpp)

# hv_portable_sources(OUT): the portable sources (tests excluded), absolute paths.
function(hv_portable_sources out)
  set(result)
  foreach(d ${HV_PORTABLE_DIRS})
    file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/hv/${d}/*.cpp)
    list(APPEND result ${srcs})
  endforeach()
  foreach(f ${HV_PORTABLE_FILES})
    list(APPEND result ${CMAKE_SOURCE_DIR}/src/hv/${f})
  endforeach()
  list(FILTER result EXCLUDE REGEX ".*_(gl)?test\\.cpp$")
  set(${out} ${result} PARENT_SCOPE)
endfunction()

# The embedded shaders (shaders/ -> generated/shaders_embedded.cpp), a portable source too.
function(hv_embed_shaders out)
  file(GLOB shaders CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/shaders/*.vert ${CMAKE_SOURCE_DIR}/shaders/*.frag
       ${CMAKE_SOURCE_DIR}/shaders/*.glsl)
  set(cpp ${CMAKE_BINARY_DIR}/generated/shaders_embedded.cpp)
  string(REPLACE ";" "|" list "${shaders}")
  add_custom_command(
    OUTPUT ${cpp}
    COMMAND ${CMAKE_COMMAND} -DOUT=${cpp} "-DFILES=${list}" -P ${CMAKE_SOURCE_DIR}/cmake/embed_shaders.cmake
    DEPENDS ${shaders} ${CMAKE_SOURCE_DIR}/cmake/embed_shaders.cmake
    COMMENT "Embedding shaders"
    VERBATIM)
  set(${out} ${cpp} PARENT_SCOPE)
endfunction()
