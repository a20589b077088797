# Writes OUT: a header with the text of IN as the C++ string constant NAME (a raw literal).
# Usage: cmake -DIN=file -DOUT=header -DNAME=identifier -P embed_text.cmake
file(READ "${IN}" text)
set(content "// Generated from ${IN} by cmake/embed_text.cmake: do not edit.\n#pragma once\ninline constexpr const char ${NAME}[] = R\"EMBED_TEXT(${text})EMBED_TEXT\";\n")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
  if(old STREQUAL content)
    return()
  endif()
endif()
file(WRITE "${OUT}" "${content}")
