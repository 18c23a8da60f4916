# Writes OUT: a C++ file that holds every shader in FILES as a string, looked up by file name
# through hv::gpu::shaderSource() (src/hv/gpu/shader_sources.h).
set(body "#include \"hv/gpu/shader_sources.h\"\n#include <map>\n#include <string>\nnamespace hv::gpu {\nnamespace {\nconst std::map<std::string, std::string>& table() {\n  static const std::map<std::string, std::string> t = {\n")
string(REPLACE "|" ";" FILES "${FILES}")
foreach(f ${FILES})
  get_filename_component(name ${f} NAME)
  file(READ ${f} content)
  set(body "${body}    {\"${name}\", R\"hvshader(${content})hvshader\"},\n")
endforeach()
set(body "${body}  };\n  return t;\n}\n}  // namespace\nconst std::string* findShaderSource(const std::string& name) {\n  auto it = table().find(name);\n  return it == table().end() ? nullptr : &it->second;\n}\nstd::vector<std::string> shaderNames() {\n  std::vector<std::string> names;\n  for (const auto& [k, v] : table()) names.push_back(k);\n  return names;\n}\n}  // namespace hv::gpu\n")
file(WRITE ${OUT}.tmp "${body}")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${OUT}.tmp ${OUT})
