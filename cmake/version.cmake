# Writes OUTPUT, a header that defines TEXR_COMMIT: the commit of the source tree SOURCE_DIR
# (its short hash and date, and whether the tree had uncommitted changes), or "unknown"
# outside a git checkout or without git. Run at every build (the texr_version target), so
# that `texr --version` names the commit a binary was built from; the header is rewritten
# only when its text changes, so an unchanged commit recompiles nothing.
set(commit "unknown")
find_program(GIT_PROGRAM git)
if(GIT_PROGRAM)
  execute_process(COMMAND "${GIT_PROGRAM}" -C "${SOURCE_DIR}" log -1 --abbrev=12 "--format=%h of %cs"
                  OUTPUT_VARIABLE found RESULT_VARIABLE result OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(result EQUAL 0 AND NOT found STREQUAL "")
    set(commit "${found}")
    execute_process(COMMAND "${GIT_PROGRAM}" -C "${SOURCE_DIR}" status --porcelain --untracked-files=no
                    OUTPUT_VARIABLE changes RESULT_VARIABLE result ERROR_QUIET)
    if(NOT result EQUAL 0 OR NOT changes STREQUAL "")
      set(commit "${commit}, with uncommitted changes")
    endif()
  endif()
endif()
set(text "// Written by cmake/version.cmake at build time.\n#define TEXR_COMMIT \"${commit}\"\n")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUTPUT}" "${text}")
endif()
