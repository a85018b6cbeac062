# oraclemesh_sanitizer_options(target): in the sanitizer build, the target's default sanitizer
# options (stack traces, the symbolizer) are built in, so ctest, libFuzzer and a user running the
# program by hand all get readable reports without setting ASAN_OPTIONS / UBSAN_OPTIONS.
function (oraclemesh_sanitizer_options target)
  if (NOT ORACLEMESH_SANITIZERS)
    return ()
  endif ()
  target_sources(${target} PRIVATE "${PROJECT_SOURCE_DIR}/Testing/SanitizerOptions.cxx")
  if (ORACLEMESH_LLVM_SYMBOLIZER)
    target_compile_definitions(${target} PRIVATE "ORACLEMESH_SYMBOLIZER=\"${ORACLEMESH_LLVM_SYMBOLIZER}\"")
  endif ()
endfunction ()
