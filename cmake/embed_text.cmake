# Writes a C++ file that holds a text file as one string constant, so a
# program serves it without an installed copy (the bridge's dashboard page).
#   cmake -DIN=page.html -DOUT=page.cpp -DNAMESPACE=nclink::bridge -DSYMBOL=kDashboardPage -P embed_text.cmake
file(READ ${IN} text)
if(text MATCHES "\\)nclink_text\"")
  message(FATAL_ERROR "${IN} holds the raw-string delimiter")
endif()
set(body "// Generated from ${IN} by cmake/embed_text.cmake.\n#include <string_view>\n\nnamespace ${NAMESPACE} {\n\nextern const std::string_view ${SYMBOL};\nconst std::string_view ${SYMBOL} = R\"nclink_text(${text})nclink_text\";\n\n}  // namespace ${NAMESPACE}\n")
# Rewrite only on change, so nothing is rebuilt for nothing.
if(EXISTS ${OUT})
  file(READ ${OUT} old)
  if(old STREQUAL body)
    return()
  endif()
endif()
file(WRITE ${OUT} "${body}")
