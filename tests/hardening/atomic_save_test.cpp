// Atomic saves under SIGKILL: a child process saves a large preset in a loop (two versions in
// turn); the parent kills it at random moments. The target must always hold one complete version,
// never a mix or a truncated file; what is left behind is at most one hidden temporary file per
// kill that landed inside a write.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <random>
#include <thread>

#include "core/friction/gms.hpp"
#include "hardening_util.hpp"

namespace gmslab::hardening {
namespace {

// A preset of about 0.5 MB (8000 GMS elements), so a save takes long enough to be hit.
Scenario big_preset(double k_scale) {
  Scenario s = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  GmsParams g = GmsParams::reference(true);
  g.alpha.assign(8000, 1.0 / 8000);
  g.k.assign(8000, 0.0);
  g.sigma.assign(8000, 0.0);
  for (std::size_t i = 0; i < g.k.size(); ++i) g.k[i] = k_scale * (1000.0 + 3.0 * i);
  s.friction = g.to_params();
  s.name = "big preset x" + std::to_string(k_scale);
  return s;
}

std::size_t temp_files_beside(const std::string& target) {
  const std::string prefix = "." + std::filesystem::path(target).filename().string() + ".tmp-";
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(temp_dir()))
    if (e.path().filename().string().rfind(prefix, 0) == 0) ++n;
  return n;
}

TEST(AtomicSave, KilledWriterLeavesTheOldOrTheNewCompleteDocument) {
  const std::string target = temp_file("killed.json");
  const Scenario a = big_preset(1.0), b = big_preset(2.0);
  const std::string text_a = to_json(a).dump(2) + "\n", text_b = to_json(b).dump(2) + "\n";
  // One save's duration on this machine: the kills land uniformly within three saves.
  const auto t0 = std::chrono::steady_clock::now();
  save_scenario(a, target);
  const auto save_us = std::chrono::duration_cast<std::chrono::microseconds>(
                           std::chrono::steady_clock::now() - t0)
                           .count();

  std::mt19937 rng(20261121);
  std::uniform_int_distribution<long> wait_us(0, 3 * save_us + 1000);
  int kills = 0, mid_write = 0, saw_a = 0, saw_b = 0;
  for (int round = 0; round < 30; ++round) {
    const std::size_t temps_before = temp_files_beside(target);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      for (unsigned i = 0;; ++i) save_scenario(i % 2 ? a : b, target);  // until killed
    }
    std::this_thread::sleep_for(std::chrono::microseconds(wait_us(rng)));
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    ++kills;

    const std::string now = read_file(target);
    ASSERT_TRUE(now == text_a || now == text_b)
        << "round " << round << ": target holds " << now.size() << " bytes, neither version ("
        << text_a.size() << " / " << text_b.size() << " bytes)";
    (now == text_a ? saw_a : saw_b)++;
    const std::size_t temps_after = temp_files_beside(target);
    EXPECT_LE(temps_after, temps_before + 1);  // at most the one file being written
    mid_write += static_cast<int>(temps_after - temps_before);
  }
  // The kills did land inside writes (else this proved nothing), and both versions were seen.
  EXPECT_GT(mid_write, 0);
  EXPECT_LE(temp_files_beside(target), static_cast<std::size_t>(kills));
  // What is there loads as one of the two versions; a normal save afterwards still works.
  const Scenario last = load_scenario(target);
  EXPECT_TRUE(last == a || last == b);
  save_scenario(a, target);
  EXPECT_EQ(read_file(target), text_a);
  std::cout << "[ info ] " << kills << " kills, " << mid_write
            << " inside a write (each left one hidden .killed.json.tmp-XXXXXX), one save takes "
            << save_us << " us, target was the first version "
            << saw_a << " times and the second " << saw_b << " times\n";
}

}  // namespace
}  // namespace gmslab::hardening
