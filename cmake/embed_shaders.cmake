# The embedded shaders (shaders/ -> generated/shaders_embedded.cpp), compiled into the gpu module.
function(hv_embed_shaders out)
  file(GLOB shaders CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/shaders/*.vert ${CMAKE_SOURCE_DIR}/shaders/*.frag
       ${CMAKE_SOURCE_DIR}/shaders/*.glsl)
  set(cpp ${CMAKE_BINARY_DIR}/generated/shaders_embedded.cpp)
  string(REPLACE ";" "|" list "${shaders}")
  add_custom_command(
    OUTPUT ${cpp}
    COMMAND ${CMAKE_COMMAND} -DOUT=${cpp} "-DFILES=${list}" -P ${CMAKE_SOURCE_DIR}/cmake/embed_shaders_script.cmake
    DEPENDS ${shaders} ${CMAKE_SOURCE_DIR}/cmake/embed_shaders_script.cmake
    COMMENT "Embedding shaders"
    VERBATIM)
  set(${out} ${cpp} PARENT_SCOPE)
endfunction()
