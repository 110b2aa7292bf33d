# Writes OUTPUT, a header that defines TEXR_COMMIT: the commit of the source tree SOURCE_DIR
# (its short hash and date, and whether the tree had uncommitted changes), or "unknown"
# where SOURCE_DIR is not the top of a git checkout (a tarball, even one unpacked inside
# another project's checkout) or git is missing. Run at every build (the texr_version
# target), so that `texr --version` names the commit a binary was built from; the header is
# rewritten only when its text changes, so an unchanged commit recompiles nothing.
# git only reads here: the checkout is trusted whoever owns it (safe.directory), and
# signatures are not checked (log.showSignature would print them with the commit).
set(commit "unknown")
find_program(GIT_PROGRAM git)
if(GIT_PROGRAM)
  set(git "${GIT_PROGRAM}" -C "${SOURCE_DIR}" -c "safe.directory=${SOURCE_DIR}" -c log.showSignature=false)
  execute_process(COMMAND ${git} rev-parse --show-toplevel
                  OUTPUT_VARIABLE top RESULT_VARIABLE result OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  get_filename_component(source "${SOURCE_DIR}" REALPATH)
  if(result EQUAL 0 AND NOT top STREQUAL "")
    get_filename_component(top "${top}" REALPATH)
  endif()
  if(result EQUAL 0 AND top STREQUAL source)
    execute_process(COMMAND ${git} log -1 --abbrev=12 --date=short "--format=%h of %cd"
                    OUTPUT_VARIABLE found RESULT_VARIABLE result OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    if(result EQUAL 0 AND found MATCHES "^[0-9a-f]+ of [0-9]+-[0-9]+-[0-9]+$")
      set(commit "${found}")
      execute_process(COMMAND ${git} status --porcelain --untracked-files=no
                      OUTPUT_VARIABLE changes RESULT_VARIABLE result ERROR_QUIET)
      if(NOT result EQUAL 0 OR NOT changes STREQUAL "")
        set(commit "${commit}, with uncommitted changes")
      endif()
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
