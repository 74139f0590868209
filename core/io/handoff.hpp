// gmslab core: a producer and one consumer thread with one slot between them, so that a long run
// computes its next chunk while the previous one is formatted, compressed and written (the trace
// writers of core/io/trace_csv.hpp and core/io/trace_file.hpp). The consumer takes the items in the
// order they were put, one at a time: the output is that of the same calls made in turn. At most
// two items exist at once (the one in the slot, the one being consumed).
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace gmslab {

template <class Item>
class Handoff {
 public:
  // `consume` runs on the consumer thread, for each item put, in order.
  explicit Handoff(std::function<void(Item&)> consume)
      : consume_(std::move(consume)), worker_([this] { run(); }) {}
  // Stops the consumer; an item not yet consumed is dropped (a run that failed).
  ~Handoff() {
    {
      const std::lock_guard<std::mutex> lock(m_);
      stop_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }
  Handoff(const Handoff&) = delete;
  Handoff& operator=(const Handoff&) = delete;

  // Waits for the slot to be free, fills it (`fill(item)`, on this thread) and hands it over.
  // Throws what an earlier `consume` threw (and puts nothing; no item after a failed one is
  // consumed).
  void put(const std::function<void(Item&)>& fill) {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait(lock, [this] { return !full_ || error_; });
    if (error_) std::rethrow_exception(error_);
    lock.unlock();  // the consumer does not touch the slot while it is not full
    fill(slot_);
    lock.lock();
    full_ = true;
    lock.unlock();
    cv_.notify_all();
  }
  // put() if the slot is free now; returns false (and fills nothing) while it holds an item that
  // the consumer has not taken yet.
  bool try_put(const std::function<void(Item&)>& fill) {
    std::unique_lock<std::mutex> lock(m_);
    if (error_) std::rethrow_exception(error_);
    if (full_) return false;
    lock.unlock();
    fill(slot_);
    lock.lock();
    full_ = true;
    lock.unlock();
    cv_.notify_all();
    return true;
  }
  // Waits until every item put has been consumed; throws what a `consume` threw.
  void drain() {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait(lock, [this] { return (!full_ && !busy_) || error_; });
    if (error_) std::rethrow_exception(error_);
  }

 private:
  void run() {
    Item item{};
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(m_);
        cv_.wait(lock, [this] { return full_ || stop_; });
        if (stop_) return;
        std::swap(item, slot_);
        full_ = false;
        busy_ = true;
      }
      cv_.notify_all();
      std::exception_ptr err;
      try {
        consume_(item);
      } catch (...) {
        err = std::current_exception();
      }
      {
        const std::lock_guard<std::mutex> lock(m_);
        busy_ = false;
        error_ = err;
      }
      cv_.notify_all();
      if (err) return;  // nothing after a failed item (put and drain throw its error)
    }
  }
  std::function<void(Item&)> consume_;
  std::mutex m_;
  std::condition_variable cv_;
  Item slot_{};
  bool full_ = false, busy_ = false, stop_ = false;
  std::exception_ptr error_;
  std::thread worker_;  // last: started once every member above exists
};

}  // namespace gmslab
