// gmslab identification: two independent searches of a fit on two threads.
//
// The searches a fit runs side by side (the warm polish and the re-chosen element table of a
// refit; the frozen-g polish and the shape search; the grid starts) share only const inputs and
// each owns its evaluator, so running them at once gives the same results as one after the other;
// the fit then takes the better as before. One level only: inside a parallel section both run on
// the calling thread (two cores; more threads would only compete).
#pragma once

#include <functional>
#include <future>
#include <memory>
#include <mutex>

#include "core/ident/fit.hpp"

namespace gmslab::ident {

inline thread_local int t_parallel_depth = 0;

// Runs a on a second thread and b on this one; returns when both are done. An exception of either
// is rethrown (b's first).
template <class A, class B>
void run_both(A&& a, B&& b) {
  if (t_parallel_depth > 0) {
    a();
    b();
    return;
  }
  auto fut = std::async(std::launch::async, [&] {
    t_parallel_depth = 1;
    a();
  });
  ++t_parallel_depth;
  try {
    b();
  } catch (...) {
    --t_parallel_depth;
    fut.wait();
    throw;
  }
  --t_parallel_depth;
  fut.get();
}

// The options with a progress callback that two threads may call (one at a time).
inline FitOptions serialised_progress(const FitOptions& o) {
  FitOptions s = o;
  if (o.progress && t_parallel_depth == 0) {
    auto m = std::make_shared<std::mutex>();
    s.progress = [m, f = o.progress](const FitProgress& p) {
      std::lock_guard<std::mutex> lock(*m);
      f(p);
    };
  }
  return s;
}

}  // namespace gmslab::ident
