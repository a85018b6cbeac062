// SPDX-License-Identifier: GPL-3.0-or-later
// Default options of the sanitizer runtimes, linked into the test programs of the sanitizer build
// (ORACLEMESH_SANITIZERS): every report has a symbolized stack trace and ends the program.
#ifndef ORACLEMESH_SYMBOLIZER
#define ORACLEMESH_SYMBOLIZER ""
#endif

extern "C" const char* __asan_default_options()
{
  static const char options[] = "detect_leaks=1:strict_string_checks=1"
                                ":check_initialization_order=1:external_symbolizer_path=" ORACLEMESH_SYMBOLIZER;
  return options;
}

extern "C" const char* __ubsan_default_options()
{
  return "print_stacktrace=1:halt_on_error=1";
}

extern "C" const char* __lsan_default_suppressions()
{
  // oneTBB frees a task_scheduler_observer's proxy lazily: a worker thread that still holds it
  // releases it when it leaves the arena, which may be after a test program's exit checks for
  // leaks (seen once in 7 runs of ParallelRefinement.AbortVertexBudgetAndBadThreads). Only TBB's
  // own allocation in observe() is exempt.
  return "leak:tbb::detail::r1::observe\n";
}
