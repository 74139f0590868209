// gmslab identification: two independent searches of a fit on two threads.
//
// The searches a fit runs side by side (the warm polish and the re-chosen element table of a
// refit; the frozen-g polish and the shape search; the grid starts) share only const inputs and
// each owns its evaluator, so running them at once gives the same results as one after the other;
// the fit then takes the better as before. One level only: inside a parallel section both run on
// the calling thread (two cores; more threads would only compete).
#pragma once

#include <atomic>
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

// fn(task, worker) for task = 0 .. count - 1 on two workers (0: this thread, 1: a second one),
// each taking the next task when free; inside a parallel section all on this thread (worker 0).
// fn must not depend on the order the tasks run in.
template <class F>
void run_tasks(std::size_t count, F&& fn) {
  if (t_parallel_depth > 0 || count < 2) {
    for (std::size_t i = 0; i < count; ++i) fn(i, 0);
    return;
  }
  std::atomic<std::size_t> next{0};
  auto worker = [&](int w) {
    try {
      for (std::size_t i; (i = next++) < count;) fn(i, w);
    } catch (...) {
      next = count;  // the other worker stops after its task
      throw;
    }
  };
  run_both([&] { worker(1); }, [&] { worker(0); });
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
