// AtomicOutput and commitAll under the conditions a run's commit meets: more
// live outputs than any fixed table holds, signals arriving during the renames,
// hundreds of outputs in one directory; the directories a run creates.
// (A rename that fails after others: tests/cli/signal_test.sh rollback, with chattr.)
#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <memory>
#include <thread>
#include <vector>

#include "formats/core/file_util.h"
#include "test_util.h"

namespace {

TEST(FileUtil, EveryLiveTemporaryIsRemovedOnRequestHoweverMany) {
  voxtest::TempDir dir;
  std::vector<std::unique_ptr<vox::AtomicOutput>> outputs;
  for (int i = 0; i < 700; ++i) {
    outputs.push_back(std::make_unique<vox::AtomicOutput>(dir.file("view_" + std::to_string(i) + ".png")));
    vox::writeFileBytes(outputs.back()->tempPath(), "half");
  }
  EXPECT_EQ(vox::removeUncommittedOutputs(), 700);  // what the CLI's signal handler does
  for (const auto& o : outputs) EXPECT_FALSE(std::filesystem::exists(o->tempPath())) << o->tempPath();
}

// What the CLI's handler does first, and what it would see if it went on.
std::atomic<int> gSignalsSeen{0}, gDeferred{0}, gSeenMidCommit{0};
std::atomic<int> gBefore{0}, gAfter{0};
extern "C" void recordSignal(int sig) {
  gSignalsSeen.fetch_add(1);
  if (vox::deferSignalDuringCommit(sig)) {
    gDeferred.fetch_add(1);
    return;
  }
  const int committed = vox::committedOutputCount();
  if (committed != gBefore.load() && committed != gAfter.load()) gSeenMidCommit.fetch_add(1);
}

TEST(FileUtil, ASignalDuringTheRenamesWaitsForAllOfThem) {
  // A busy machine may leave the sending thread without a core for a whole
  // commit: rounds of 600 outputs are committed until signals have landed
  // during the renames (usually the first round), each round checked.
  constexpr int kOutputs = 600, kMaxRounds = 30;
  struct sigaction sa {}, old {};
  sa.sa_handler = recordSignal;
  sa.sa_flags = SA_RESTART;
  sigemptyset(&sa.sa_mask);
  ASSERT_EQ(sigaction(SIGUSR1, &sa, &old), 0);
  for (int round = 0; round < kMaxRounds && gDeferred.load() == 0; ++round) {
    voxtest::TempDir dir;
    std::vector<std::unique_ptr<vox::AtomicOutput>> outputs;
    std::vector<vox::AtomicOutput*> all;
    for (int i = 0; i < kOutputs; ++i) {
      outputs.push_back(std::make_unique<vox::AtomicOutput>(dir.file("out_" + std::to_string(i) + ".bin")));
      vox::writeFileBytes(outputs.back()->tempPath(), "new");
      all.push_back(outputs.back().get());
    }
    gBefore = vox::committedOutputCount();
    gAfter = gBefore + kOutputs;
    std::atomic<bool> done{false};
    const pthread_t committer = pthread_self();
    const int seenBefore = gSignalsSeen.load();
    std::thread sender([&] {  // signals the committing thread without pause until it is done
      while (!done.load()) pthread_kill(committer, SIGUSR1);
    });
    while (gSignalsSeen.load() == seenBefore) std::this_thread::yield();  // the sender is running
    vox::commitAll(all);
    done = true;
    sender.join();
    EXPECT_EQ(gSeenMidCommit.load(), 0) << "a handler ran between two renames (round " << round << ")";
    EXPECT_EQ(vox::committedOutputCount(), gAfter.load());
    for (int i = 0; i < kOutputs; ++i)
      EXPECT_EQ(vox::readFileBytes(dir.file("out_" + std::to_string(i) + ".bin")), "new");
  }
  sigaction(SIGUSR1, &old, nullptr);
  EXPECT_GT(gDeferred.load(), 0) << "no signal arrived during the renames in " << kMaxRounds
                                 << " rounds: the test proves nothing";
}

// A pid that no longer runs.
pid_t deadPid() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  return child;
}

// A temporary of `finalName` in `dir` as a dead run of this host left it.
std::string staleTemporary(const voxtest::TempDir& dir, const std::string& finalName, pid_t pid) {
  voxtest::TempDir elsewhere;
  const vox::AtomicOutput probe(elsewhere.file(finalName));  // its name gives this host's tag
  const std::string t = std::filesystem::path(probe.tempPath()).filename().string();
  const size_t pidAt = t.find('-', t.rfind(".tmp-") + 5) + 1;
  const std::string path = dir.file(t.substr(0, pidAt) + std::to_string(pid) + "-0");
  voxtest::writeText(path, "x");
  return path;
}

TEST(FileUtil, ADirectoryIsReadForStaleTemporariesOncePerRun) {
  // 700 outputs in one directory read it once, not 700 times: the stale
  // temporaries there when the run first writes to it are found (by the
  // output of their name, however the directory is spelled), one left after
  // that is the next run's.
  voxtest::TempDir dir;
  const pid_t dead = deadPid();
  const std::string before = staleTemporary(dir, "b.png", dead);
  if (before.find(".tmp-00000000-") != std::string::npos) GTEST_SKIP() << "this host's name hashes to 00000000";
  vox::AtomicOutput a(dir.file("a.png"));
  EXPECT_TRUE(std::filesystem::exists(before)) << "another output's stale temporary was removed";
  const std::string after = staleTemporary(dir, "c.png", dead);
  vox::AtomicOutput b((dir.path() / "." / "b.png").string());
  EXPECT_FALSE(std::filesystem::exists(before)) << "a stale temporary there at the first output was kept";
  vox::AtomicOutput c(dir.file("c.png"));
  EXPECT_TRUE(std::filesystem::exists(after)) << "the directory was read again at a later output";
  // The next run (a forked child is another process) reads it again.
  const pid_t next = fork();
  if (next == 0) {
    const vox::AtomicOutput again(dir.file("c.png"));
    _exit(std::filesystem::exists(after) ? 1 : 0);
  }
  int status = 0;
  waitpid(next, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the next run kept the stale temporary";
  EXPECT_FALSE(std::filesystem::exists(after));
}

TEST(FileUtil, CreatedDirectoriesAreRemovedDeepestFirstWhileEmpty) {
  namespace fs = std::filesystem;
  voxtest::TempDir dir;
  fs::create_directory(dir.path() / "existing");
  {
    // A signal: the temporaries go first, then every level made, deepest first.
    vox::CreatedDirectories made;
    made.create(dir.file("existing/new/deeper/atlas"));
    EXPECT_EQ(made.made(), (std::vector<std::string>{dir.file("existing/new/deeper/atlas"),
                                                     dir.file("existing/new/deeper"), dir.file("existing/new")}));
    vox::AtomicOutput out(dir.file("existing/new/deeper/atlas/a.png"));
    vox::writeFileBytes(out.tempPath(), "half");
    EXPECT_EQ(vox::removeUncommittedOutputs(), 1);  // what the CLI's signal handler does
    EXPECT_EQ(vox::removeCreatedDirectories(), 3);
    EXPECT_FALSE(fs::exists(dir.file("existing/new")));
    EXPECT_TRUE(fs::is_directory(dir.file("existing"))) << "a directory the run did not make was removed";
  }
  {
    // A level holding anything else stays, with its parents.
    vox::CreatedDirectories made;
    made.create(dir.file("existing/new/deeper/atlas/"));
    ASSERT_EQ(made.made().size(), 3u) << "\"dir/\" is dir";
    voxtest::writeText(dir.file("existing/new/mine.txt"), "a user's file");
    EXPECT_EQ(vox::removeCreatedDirectories(), 2);
    EXPECT_FALSE(fs::exists(dir.file("existing/new/deeper")));
    EXPECT_TRUE(fs::exists(dir.file("existing/new/mine.txt")));
    fs::remove(dir.file("existing/new/mine.txt"));
  }  // a failed run: its destructor removes what is left of it
  EXPECT_FALSE(fs::exists(dir.file("existing/new")));
  {
    vox::CreatedDirectories made;
    made.create(dir.file("kept/sub"));
    made.keep();  // the run succeeded
    EXPECT_EQ(vox::removeCreatedDirectories(), 0);
  }
  EXPECT_TRUE(fs::is_directory(dir.file("kept/sub")));
  // An existing directory is fine and not made; a file in the way is refused.
  {
    vox::CreatedDirectories made;
    made.create(dir.file("kept/sub"));
    EXPECT_TRUE(made.made().empty());
    voxtest::writeText(dir.file("afile"), "x");
    EXPECT_TRUE(voxtest::throwsVoxError([&] { made.create(dir.file("afile/sub")); }, vox::ErrorKind::Io,
                                        {dir.file("afile/sub"), "cannot create the output directory", "Not a directory"}));
  }
}

}  // namespace
