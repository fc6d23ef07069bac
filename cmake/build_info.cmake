# Runs at every build (target rb_build_info, apps/CMakeLists.txt): writes the git revision, dirty flag
# and commit time into the header that names the source a binary was built from (docs/BUILD.md).
# Inputs: -DSRC=<source dir> -DOUT=<header> -DTEMPLATE=<header.in> -DVERSION=<project version>
set(RB_GIT_REVISION "unknown")
set(RB_GIT_DIRTY 0)
set(RB_GIT_TIME "")
find_program(GIT git)
if(GIT)
  execute_process(COMMAND ${GIT} -C ${SRC} rev-parse --short=12 HEAD
    OUTPUT_VARIABLE rev RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(rc EQUAL 0 AND rev)
    set(RB_GIT_REVISION "${rev}")
    execute_process(COMMAND ${GIT} -C ${SRC} status --porcelain --untracked-files=no
      OUTPUT_VARIABLE st RESULT_VARIABLE rc2 OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    if(rc2 EQUAL 0 AND st)
      set(RB_GIT_DIRTY 1)
    endif()
    execute_process(COMMAND ${GIT} -C ${SRC} log -1 --format=%cI
      OUTPUT_VARIABLE ct OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    set(RB_GIT_TIME "${ct}")
  endif()
endif()
set(RB_VERSION "${VERSION}")
configure_file(${TEMPLATE} ${OUT} @ONLY)
