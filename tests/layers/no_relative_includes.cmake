# A library source reaches only the headers its layer's include roots hold: an include through
# "../" would step around them, so none may use one.
file(GLOB_RECURSE sources "${SOURCE_DIR}/src/*.cpp" "${SOURCE_DIR}/src/*.hpp"
     "${SOURCE_DIR}/include/*.hpp")
set(found "")
foreach(source ${sources})
  file(STRINGS ${source} lines REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<][^\">]*\\.\\./")
  if(lines)
    string(APPEND found "\n  ${source}: ${lines}")
  endif()
endforeach()
if(found)
  message(FATAL_ERROR "includes through ../ step around the layers:${found}")
endif()
