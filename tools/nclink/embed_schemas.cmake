# Writes a C++ file holding the JSON Schemas of docs/schema/ as string
# literals, so `nclink config` works without the installed copies.
#   cmake -DOUT=file.cpp -DSCHEMAS="a.schema.json|b.schema.json" -P embed_schemas.cmake
set(body "// Generated from docs/schema/*.schema.json by tools/nclink/embed_schemas.cmake.\n#include \"config_kinds.hpp\"\n\nnamespace nclink::cli {\n\nconst std::vector<EmbeddedSchema>& embedded_schemas() {\n    static const std::vector<EmbeddedSchema> schemas = {\n")
string(REPLACE "|" ";" SCHEMAS "${SCHEMAS}")
foreach(schema IN LISTS SCHEMAS)
  get_filename_component(name ${schema} NAME)
  string(REGEX REPLACE "\\.schema\\.json$" "" name "${name}")
  file(READ ${schema} text)
  if(text MATCHES "\\)nclink_schema\"")
    message(FATAL_ERROR "${schema} holds the raw-string delimiter")
  endif()
  string(APPEND body "        {\"${name}\", R\"nclink_schema(${text})nclink_schema\"},\n")
endforeach()
string(APPEND body "    };\n    return schemas;\n}\n\n}  // namespace nclink::cli\n")
# Rewrite only on change, so the program is not relinked for nothing.
if(EXISTS ${OUT})
  file(READ ${OUT} old)
  if(old STREQUAL body)
    return()
  endif()
endif()
file(WRITE ${OUT} "${body}")
