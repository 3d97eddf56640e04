#pragma once
/// \file
/// A thread count given by a user (the CLI's --jobs, Python's jobs= and threads=, an options
/// struct's threads), refused by the option's name: threads.h's check as an InputError.

namespace medspheres {

/// \throws InputError (kOutOfRange) naming the option \p field ("jobs", "threads") and the
///   problem (threads_problem, threads.h) unless 0 <= threads <= kMaxThreads.
void check_threads_option(int threads, const char* field);

}  // namespace medspheres
