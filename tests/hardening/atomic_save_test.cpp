// Atomic saves under SIGKILL: a child process saves a large preset in a loop (two versions in
// turn); the parent kills it at random moments. The target must always hold one complete version,
// never a mix or a truncated file; a killed writer leaves at most the one hidden temporary file it
// was writing, and the next save removes it.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
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

// Temporary files beside `target`: all of them, or those written by process `pid` only.
std::size_t temp_files_beside(const std::string& target, pid_t pid = 0) {
  std::string prefix = "." + std::filesystem::path(target).filename().string() + ".tmp-";
  if (pid != 0) prefix += std::to_string(pid) + "-";
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(temp_dir()))
    if (e.path().filename().string().rfind(prefix, 0) == 0) ++n;
  return n;
}

// A process that has exited and been reaped: its id names no live process (until reused).
pid_t reaped_child() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return pid;
}

TEST(AtomicSave, KilledWriterLeavesTheOldOrTheNewCompleteDocument) {
  const std::string target = temp_file("killed.json");
  const Scenario a = big_preset(1.0), b = big_preset(2.0);
  const std::string text_a = to_json(a).dump(2) + "\n", text_b = to_json(b).dump(2) + "\n";
  // The child writes the serialised texts directly, so nearly all of its time is spent inside
  // write_file_atomic (temporary file open) and most kills land inside a write. One write's
  // duration on this machine sets the kill times: uniform within three writes.
  const auto t0 = std::chrono::steady_clock::now();
  save_scenario(a, target);
  const auto save_us = std::chrono::duration_cast<std::chrono::microseconds>(
                           std::chrono::steady_clock::now() - t0)
                           .count();

  std::mt19937 rng(20261121);
  std::uniform_int_distribution<long> wait_us(0, 3 * save_us + 1000);
  int kills = 0, mid_write = 0, saw_a = 0, saw_b = 0;
  // Kill until at least 5 kills have landed inside a write (proof the test exercised the
  // dangerous window), at least 20 kills in all, and at most 400.
  while (kills < 400 && (kills < 20 || mid_write < 5)) {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      for (unsigned i = 0;; ++i) write_file_atomic(target, i % 2 ? text_a : text_b);
    }
    std::this_thread::sleep_for(std::chrono::microseconds(wait_us(rng)));
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    ++kills;

    const std::string now = read_file(target);
    ASSERT_TRUE(now == text_a || now == text_b)
        << "kill " << kills << ": target holds " << now.size() << " bytes, neither version ("
        << text_a.size() << " / " << text_b.size() << " bytes)";
    (now == text_a ? saw_a : saw_b)++;
    const std::size_t left = temp_files_beside(target, pid);
    EXPECT_LE(left, 1u) << "a killed writer can leave at most the one file it was writing";
    mid_write += static_cast<int>(left);
  }
  EXPECT_GE(mid_write, 5) << "the kills did not land inside writes, so this proved nothing";
  EXPECT_GT(saw_a, 0);
  EXPECT_GT(saw_b, 0);
  // What is there loads as one of the two versions; the next normal save works and removes every
  // temporary file the killed writers left.
  const Scenario last = load_scenario(target);
  EXPECT_TRUE(last == a || last == b);
  save_scenario(a, target);
  EXPECT_EQ(read_file(target), text_a);
  EXPECT_EQ(temp_files_beside(target), 0u);
  std::cout << "[ info ] " << kills << " kills, " << mid_write
            << " inside a write, one save takes " << save_us
            << " us, target was the first version " << saw_a << " times and the second "
            << saw_b << " times\n";
}

TEST(AtomicSave, StaleTemporariesOfDeadWritersAreRemovedAndLiveOnesKept) {
  const std::string target = temp_file("stale.json");
  const std::string dir = temp_dir().string() + "/";
  const pid_t dead = reaped_child();
  const std::string dead_tmp = dir + ".stale.json.tmp-" + std::to_string(dead) + "-abc123";
  const std::string own_tmp = dir + ".stale.json.tmp-" + std::to_string(::getpid()) + "-abc123";
  const std::string parent_tmp = dir + ".stale.json.tmp-" + std::to_string(::getppid()) + "-x";
  const std::string odd_tmp = dir + ".stale.json.tmp-notapid";   // not ours: never touched
  const std::string other = dir + ".other.json.tmp-" + std::to_string(dead) + "-abc123";
  for (const auto& f : {dead_tmp, own_tmp, parent_tmp, odd_tmp, other}) write_file_atomic(f, "x");

  EXPECT_EQ(remove_stale_temporaries(target), 1u);
  EXPECT_FALSE(std::filesystem::exists(dead_tmp));
  EXPECT_TRUE(std::filesystem::exists(own_tmp));     // this process may be writing it
  EXPECT_TRUE(std::filesystem::exists(parent_tmp));  // a live process (ctest) may be writing it
  EXPECT_TRUE(std::filesystem::exists(odd_tmp));
  EXPECT_TRUE(std::filesystem::exists(other));       // belongs to another file
}

// A session the window cannot read is moved aside before the window's exit save could overwrite it.
TEST(AtomicSave, UnreadableFileIsSetAsideNotOverwritten) {
  const std::string path = temp_file("session.json");
  write_file_atomic(path, "{ \"schema_version\": 99 }");
  EXPECT_THROW(load_scenario(path), InputError);
  const std::string kept = set_aside(path);
  EXPECT_EQ(kept, path + ".unreadable");
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_EQ(read_file(kept), "{ \"schema_version\": 99 }");
  write_file_atomic(path, "second");
  EXPECT_EQ(set_aside(path), path + ".unreadable-2");  // the first one is not overwritten either
  EXPECT_EQ(read_file(kept), "{ \"schema_version\": 99 }");
  EXPECT_EQ(read_file(path + ".unreadable-2"), "second");
  try {
    set_aside(path);  // gone now
    ADD_FAILURE() << "moved a missing file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

// Open descriptors of this process.
std::size_t open_fds() {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator("/proc/self/fd")) ++n;
  return n;
}

// A save over an existing file: the target holds the new text at once; a reader that had the old
// file open still reads it whole (the old file is released, not changed: its last link is gone and
// its blocks go when the last descriptor closes); a symlink at the target is replaced, not
// followed; and a hundred saves in a row leave no descriptor open.
TEST(AtomicSave, ReplacingAFileReleasesTheOldOneWithoutTouchingIt) {
  const std::string path = temp_file("replaced.csv");
  const std::string first(3u << 20, 'a'), second(2u << 20, 'b');
  write_file_atomic(path, first);
  const int reader = ::open(path.c_str(), O_RDONLY);
  ASSERT_GE(reader, 0);
  write_file_atomic(path, second);
  EXPECT_EQ(read_file(path), second);
  struct stat st {};
  ASSERT_EQ(::fstat(reader, &st), 0);
  EXPECT_EQ(st.st_nlink, 0u);  // unlinked by the rename
  EXPECT_EQ(static_cast<std::size_t>(st.st_size), first.size());
  std::string back(first.size(), '\0');
  EXPECT_EQ(::pread(reader, back.data(), back.size(), 0), static_cast<ssize_t>(back.size()));
  EXPECT_EQ(back, first);
  ::close(reader);
  EXPECT_EQ(temp_files_beside(path), 0u);

  const std::string target = temp_file("link_target.txt"), link = temp_file("link.txt");
  write_file_atomic(target, "target");
  std::filesystem::create_symlink(target, link);
  write_file_atomic(link, "saved");
  EXPECT_FALSE(std::filesystem::is_symlink(link));
  EXPECT_EQ(read_file(link), "saved");
  EXPECT_EQ(read_file(target), "target");

  const std::size_t before = open_fds();
  for (int i = 0; i < 100; ++i) write_file_atomic(path, i % 2 ? first : second);
  std::size_t after = open_fds();
  for (int wait = 0; wait < 200 && after > before; ++wait) {  // the releases run on their threads
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    after = open_fds();
  }
  EXPECT_EQ(after, before);
  EXPECT_EQ(read_file(path), first);
}

}  // namespace
}  // namespace gmslab::hardening
