// Handoff (core/io/handoff.hpp): the consumer thread sees every item in the order put, whatever the
// timing of either side; an error of the consumer is thrown by the next put or drain; and the trace
// writers built on it give the text of doing everything in turn, also when the sink fails.
#include "core/io/handoff.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/trace_csv.hpp"
#include "test_util.hpp"

namespace gmslab {
namespace {

TEST(Handoff, EveryItemInOrderWhateverTheTiming) {
  std::mt19937 rng(4711);
  for (int round = 0; round < 20; ++round) {
    std::vector<int> seen;
    std::vector<int> delays(200);
    for (auto& d : delays) d = static_cast<int>(rng() % 3);  // 0, 1 or 2 x 50 us on either side
    const int n = 50 + static_cast<int>(rng() % 150);
    {
      Handoff<std::vector<int>> h([&](std::vector<int>& item) {
        std::this_thread::sleep_for(
            std::chrono::microseconds(50 * delays[static_cast<std::size_t>(item[0]) % 200]));
        seen.insert(seen.end(), item.begin(), item.end());
      });
      for (int i = 0; i < n; ++i) {
        std::this_thread::sleep_for(
            std::chrono::microseconds(50 * delays[(static_cast<std::size_t>(i) * 7) % 200]));
        h.put([&](std::vector<int>& item) { item.assign({i, i}); });
      }
      h.drain();
    }
    ASSERT_EQ(seen.size(), 2u * static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(seen[2 * static_cast<std::size_t>(i)], i);
      EXPECT_EQ(seen[2 * static_cast<std::size_t>(i) + 1], i);
    }
  }
}

// try_put fills the slot only when it is free: while the consumer is busy with one item and a
// second waits in the slot, it refuses (and fills nothing); once the consumer takes the second,
// it accepts. Every accepted item is consumed once, in order.
TEST(Handoff, TryPutRefusesWhileTheSlotHoldsAnItem) {
  std::mutex gate;
  std::unique_lock<std::mutex> hold(gate);  // the consumer waits on this inside its first item
  std::vector<int> seen;
  {
    Handoff<int> h([&](int& item) {
      const std::lock_guard<std::mutex> wait(gate);
      seen.push_back(item);
    });
    int fills = 0;
    EXPECT_TRUE(h.try_put([&](int& item) { item = 1, ++fills; }));
    // The consumer takes item 1 (and blocks on the gate); then the slot is free for item 2.
    while (!h.try_put([&](int& item) { item = 2, ++fills; })) std::this_thread::yield();
    int refused = 0;
    for (int i = 0; i < 5; ++i)
      refused += h.try_put([&](int& item) { item = 99, ++fills; }) ? 0 : 1;
    EXPECT_EQ(refused, 5);  // item 2 waits in the slot while the consumer holds item 1
    EXPECT_EQ(fills, 2);
    hold.unlock();
    while (!h.try_put([&](int& item) { item = 3, ++fills; })) std::this_thread::yield();
    h.drain();
    EXPECT_EQ(fills, 3);
  }
  EXPECT_EQ(seen, (std::vector<int>{1, 2, 3}));
}

TEST(Handoff, AConsumerErrorIsThrownByTheNextPutOrDrain) {
  int consumed = 0;
  Handoff<int> h([&](int& item) {
    ++consumed;
    if (item == 3) throw IoError("disk full at item 3");
  });
  int thrown_at = -1;
  try {
    for (int i = 0; i < 100; ++i) {
      thrown_at = i;
      h.put([&](int& item) { item = i; });
    }
    h.drain();
    thrown_at = 100;
  } catch (const IoError& e) {
    EXPECT_STREQ(e.what(), "disk full at item 3");
  }
  EXPECT_GE(thrown_at, 4);  // items 0..3 were put first
  EXPECT_LE(thrown_at, 5);  // at most one more put before the error is seen
  EXPECT_EQ(consumed, 4);   // nothing after the failing item
  EXPECT_THROW(h.drain(), IoError);
}

// The CSV stream's sink failing on its 3rd piece: stream_trace_csv throws that error, and the
// pieces before it are the start of the text written in turn.
TEST(Handoff, TheCsvStreamThrowsWhatItsSinkThrows) {
  Scenario sc = load_scenario(test_util::preset_path("fig4_stick_slip.json"));
  std::string whole;
  stream_trace_csv(sc, [&](std::string_view s) { whole += s; });
  std::string got;
  int pieces = 0;
  EXPECT_THROW(stream_trace_csv(sc,
                                [&](std::string_view s) {
                                  if (++pieces == 3) throw IoError("no space");
                                  got += s;
                                }),
               IoError);
  EXPECT_EQ(pieces, 3);
  EXPECT_GT(got.size(), 1000u);
  EXPECT_EQ(whole.compare(0, got.size(), got), 0);
}

}  // namespace
}  // namespace gmslab
