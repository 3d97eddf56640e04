#pragma once
/// \file
/// A thread count given by a user (the CLI's --jobs, Python's jobs=), refused by the
/// option's name: the check of threads.h as an InputError, for public entry points.

namespace medspheres {

/// \throws InputError (kOutOfRange) naming the option \p field ("jobs", "threads") and the
///   problem (threads_problem, threads.h) unless 0 <= threads <= kMaxThreads.
void check_threads_option(int threads, const char* field);

}  // namespace medspheres
