# The modules of histoview and the layering between them (docs/architecture.md).
#
# Each module is one static library, hv_<name>, built from the sources of its folder(s) under
# src/hv/ (tests excluded). Its headers are reachable only through an include root of its own,
# ${CMAKE_BINARY_DIR}/include/<name>/, which holds links to exactly the module's headers: a source
# sees the headers of its own module and of the modules it links, nothing else. An include that
# runs against the layering (a lower module including a higher one, or a portable module
# including a native one) is then a compile error ("hv/...: No such file or directory"), not a
# convention.
#
#   hv_module(<name> DIRS <folder>... [PORTABLE] [DEPS <module>...] [PRIVATE_DEPS <module>...]
#             [EXTERNAL <ext>...] [PRIVATE_EXTERNAL <ext>...])
#
# DEPS are modules whose headers this module's headers include (linked PUBLIC); PRIVATE_DEPS are
# used by its sources only. EXTERNAL / PRIVATE_EXTERNAL name third-party libraries by the short
# names of hv_ext_<ext> targets (defined for the native build in CMakeLists.txt and for the
# browser build in cmake/web.cmake), so one table serves both builds. PORTABLE modules build for
# the browser too (WebAssembly + WebGL2): they may depend only on portable modules and on
# header-only libraries, stb and GLES 3.
#
# The list of modules, their folders and dependencies is recorded (global properties HV_MODULES,
# HV_MODULE_<name>_*) for the link check (tests/portable_link_check.cpp) and for
# `cmake -P cmake/module_table.cmake`, which writes the table of docs/architecture.md.

set_property(GLOBAL PROPERTY HV_MODULES "")

function(hv_module name)
  cmake_parse_arguments(M "PORTABLE" "EXCLUDE" "DIRS;DEPS;PRIVATE_DEPS;EXTERNAL;PRIVATE_EXTERNAL;EXTRA_SOURCES" ${ARGN})
  if(EMSCRIPTEN AND NOT M_PORTABLE)
    return()
  endif()
  set(sources)
  set(root ${CMAKE_BINARY_DIR}/include/${name})
  file(REMOVE_RECURSE ${root})
  foreach(dir ${M_DIRS})
    file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/hv/${dir}/*.cpp)
    list(FILTER srcs EXCLUDE REGEX ".*_(gl)?test\\.cpp$")
    if(M_EXCLUDE)
      list(FILTER srcs EXCLUDE REGEX "${M_EXCLUDE}")
    endif()
    list(APPEND sources ${srcs})
    file(GLOB headers CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/hv/${dir}/*.h)
    file(MAKE_DIRECTORY ${root}/hv/${dir})
    foreach(h ${headers})
      get_filename_component(leaf ${h} NAME)
      file(CREATE_LINK ${h} ${root}/hv/${dir}/${leaf} SYMBOLIC)
    endforeach()
  endforeach()
  list(APPEND sources ${M_EXTRA_SOURCES})
  set(target hv_${name})
  if(sources)
    add_library(${target} STATIC ${sources})
    target_include_directories(${target} PUBLIC ${root})
    target_compile_options(${target} PRIVATE ${HV_WARNINGS})
    set(pub PUBLIC)
    set(priv PRIVATE)
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${root})
    set(pub INTERFACE)
    set(priv INTERFACE)
  endif()
  foreach(dep ${M_DEPS})
    target_link_libraries(${target} ${pub} hv_${dep})
  endforeach()
  foreach(dep ${M_PRIVATE_DEPS})
    target_link_libraries(${target} ${priv} hv_${dep})
  endforeach()
  foreach(ext ${M_EXTERNAL})
    target_link_libraries(${target} ${pub} hv_ext_${ext})
  endforeach()
  foreach(ext ${M_PRIVATE_EXTERNAL})
    target_link_libraries(${target} ${priv} hv_ext_${ext})
  endforeach()
  set_property(GLOBAL APPEND PROPERTY HV_MODULES ${name})
  set_property(GLOBAL PROPERTY HV_MODULE_${name}_DIRS ${M_DIRS})
  set_property(GLOBAL PROPERTY HV_MODULE_${name}_DEPS ${M_DEPS})
  set_property(GLOBAL PROPERTY HV_MODULE_${name}_PRIVATE_DEPS ${M_PRIVATE_DEPS})
  set_property(GLOBAL PROPERTY HV_MODULE_${name}_PORTABLE ${M_PORTABLE})
endfunction()

# The modules, lowest first. A module may depend only on modules above it in this list.
function(hv_define_modules)
  # Portable: the core that also runs in the browser.
  hv_module(util PORTABLE DIRS util EXTERNAL threads)
  hv_module(math PORTABLE DIRS math EXTERNAL glm)
  hv_module(camera PORTABLE DIRS camera DEPS math util PRIVATE_EXTERNAL eigen)
  hv_module(image PORTABLE DIRS image DEPS util EXTERNAL glm PRIVATE_EXTERNAL stb)
  hv_module(scene PORTABLE DIRS scene DEPS camera math util PRIVATE_EXTERNAL eigen nanoflann)
  # Traffic: trajectories from a simulator, sampled in time and lifted onto the terrain.
  hv_module(traffic PORTABLE DIRS traffic DEPS math scene util)
  hv_module(io PORTABLE DIRS io DEPS camera scene util PRIVATE_DEPS traffic EXTERNAL json)
  hv_module(ibr PORTABLE DIRS ibr DEPS camera image scene util PRIVATE_EXTERNAL nanoflann stb)
  hv_module(gpu PORTABLE DIRS gpu DEPS image util EXTERNAL gles glm EXTRA_SOURCES ${HV_SHADER_CPP})
  # Layered projective texture maps (2003): visibility layers, image-layer clustering, sub-image frusta.
  hv_module(layers PORTABLE DIRS layers DEPS camera image EXTERNAL glm)
  # The renderer without GL: settings and their schema, the frame, the frame builder, the backend
  # interface and the null backend (tested on the CPU). render/renderer.h is its API; the class is
  # implemented in render_gl, over the GLES backend and its passes.
  hv_module(render PORTABLE DIRS render EXCLUDE ".*/render/renderer\\.cpp$" DEPS camera ibr image layers scene traffic util
            PRIVATE_EXTERNAL json)
  hv_module(render_gl PORTABLE DIRS render/gl EXTRA_SOURCES ${CMAKE_SOURCE_DIR}/src/hv/render/renderer.cpp
            DEPS gpu render PRIVATE_DEPS camera ibr image layers scene util)
  hv_module(viewer PORTABLE DIRS viewer DEPS camera image util PRIVATE_DEPS scene)
  hv_module(pose PORTABLE DIRS pose DEPS camera util EXTERNAL glm PRIVATE_EXTERNAL eigen)
  # Native: GDAL/OGR/PROJ, GEOS, Embree, Assimp, libpng, EGL, GLFW + Dear ImGui, CLI11.
  hv_module(image_native DIRS image/native DEPS image PRIVATE_EXTERNAL png)
  hv_module(scene_native DIRS scene/native DEPS scene util PRIVATE_EXTERNAL geos embree)
  hv_module(io_native DIRS io/native io/native/private DEPS camera scene scene_native traffic util PRIVATE_DEPS io
            PRIVATE_EXTERNAL gdal proj assimp pugixml json tinygltf)
  hv_module(gpu_egl DIRS gpu/platform/egl PRIVATE_DEPS gpu util PRIVATE_EXTERNAL egl)
  # Layers from ray casts, their pre-fill from the other photographs, OpenRaster files (libzip).
  hv_module(layers_native DIRS layers/native DEPS camera image layers scene util PRIVATE_DEPS image_native scene_native
            PRIVATE_EXTERNAL zip pugixml json)
  hv_module(eval DIRS eval DEPS camera image render scene util PRIVATE_DEPS image_native render_gl
            PRIVATE_EXTERNAL json)
  hv_module(session DIRS session DEPS gpu render render_gl scene util PRIVATE_DEPS camera io io_native gpu_egl layers
            layers_native viewer
            PRIVATE_EXTERNAL cli11 stb json)
  hv_module(demo DIRS demo DEPS camera image scene scene_native PRIVATE_DEPS image_native io io_native
            PRIVATE_EXTERNAL json gdal)
  if(HV_HAVE_VIEWER)
    hv_module(gpu_glfw DIRS gpu/platform/glfw DEPS gpu PRIVATE_EXTERNAL glfw imgui)
    hv_module(viewer_desktop DIRS viewer/desktop EXCLUDE ".*/no_viewer\\.cpp$" DEPS session
              PRIVATE_DEPS camera gpu gpu_glfw image image_native io pose scene_native viewer PRIVATE_EXTERNAL glfw imgui)
  else()
    # Without GLFW and Dear ImGui, `histoview view` says what to install (no_viewer.cpp).
    hv_module(viewer_desktop DIRS viewer/desktop EXCLUDE ".*/viewer_app\\.cpp$" DEPS session)
  endif()
  hv_module(app DIRS app DEPS camera io render PRIVATE_DEPS demo eval gpu image image_native io_native layers
            layers_native pose scene
            scene_native session util viewer viewer_desktop PRIVATE_EXTERNAL cli11 json)
  # Header-only helpers of the tests.
  hv_module(testing DIRS testing EXTERNAL glm)
  hv_module(render_testing DIRS render/testing DEPS testing)
endfunction()

# Writes the module table of docs/architecture.md (markdown) to `out`, from the modules as
# defined: the `architecture_table` test fails when the page's copy differs.
function(hv_write_module_table out)
  get_property(modules GLOBAL PROPERTY HV_MODULES)
  set(text "| module (library) | folders under src/hv | builds for the browser | depends on (public) | uses (private) |\n")
  string(APPEND text "|---|---|---|---|---|\n")
  foreach(m ${modules})
    get_property(dirs GLOBAL PROPERTY HV_MODULE_${m}_DIRS)
    get_property(deps GLOBAL PROPERTY HV_MODULE_${m}_DEPS)
    get_property(pdeps GLOBAL PROPERTY HV_MODULE_${m}_PRIVATE_DEPS)
    get_property(portable GLOBAL PROPERTY HV_MODULE_${m}_PORTABLE)
    if(portable)
      set(p "yes")
    else()
      set(p "no")
    endif()
    list(JOIN dirs ", " d)
    list(JOIN deps ", " dp)
    list(JOIN pdeps ", " pp)
    string(APPEND text "| `hv_${m}` | ${d} | ${p} | ${dp} | ${pp} |\n")
  endforeach()
  file(WRITE ${out}.tmp "${text}")
  execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${out}.tmp ${out})
endfunction()
