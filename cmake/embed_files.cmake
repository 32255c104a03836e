# Writes OUTPUT: a C++ source that holds the files of DIR matching GLOB (relative to DIR, e.g.
# "*.mustache" or "*/*.urdf") as string constants, keyed by their path relative to DIR, returned
# by `const std::map<std::string, std::string>& NAMESPACE::FUNCTION()` declared in HEADER. Used
# for templates/ (the generator runs from any directory) and robots/ (the fuzzers run from any
# directory). Run as: cmake -DDIR=.. -DGLOB=.. -DHEADER=.. -DNAMESPACE=.. -DFUNCTION=.. -DOUTPUT=.. -P this
file(GLOB files RELATIVE ${DIR} ${DIR}/${GLOB})
list(SORT files)
set(body "// Generated from ${GLOB} by cmake/embed_files.cmake. Do not edit.\n#include \"${HEADER}\"\n\nnamespace ${NAMESPACE} {\n\nconst std::map<std::string, std::string>& ${FUNCTION}() {\n  static const std::map<std::string, std::string> files = {\n")
foreach(name ${files})
  file(READ ${DIR}/${name} text)
  string(FIND "${text}" ")embedded\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "${name} contains the raw-string delimiter")
  endif()
  string(APPEND body "      {\"${name}\", R\"embedded(${text})embedded\"},\n")
endforeach()
string(APPEND body "  };\n  return files;\n}\n\n}  // namespace ${NAMESPACE}\n")
file(WRITE ${OUTPUT}.tmp "${body}")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUTPUT}.tmp)
