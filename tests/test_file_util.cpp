// AtomicOutput and commitAll under the conditions a run's commit meets: more
// live outputs than any fixed table holds, signals arriving during the renames.
// (A rename that fails after others: tests/cli/signal_test.sh rollback, with chattr.)
#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>

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
  voxtest::TempDir dir;
  constexpr int kOutputs = 600;
  std::vector<std::unique_ptr<vox::AtomicOutput>> outputs;
  std::vector<vox::AtomicOutput*> all;
  for (int i = 0; i < kOutputs; ++i) {
    outputs.push_back(std::make_unique<vox::AtomicOutput>(dir.file("out_" + std::to_string(i) + ".bin")));
    vox::writeFileBytes(outputs.back()->tempPath(), "new");
    all.push_back(outputs.back().get());
  }
  struct sigaction sa {}, old {};
  sa.sa_handler = recordSignal;
  sa.sa_flags = SA_RESTART;
  sigemptyset(&sa.sa_mask);
  ASSERT_EQ(sigaction(SIGUSR1, &sa, &old), 0);
  gBefore = vox::committedOutputCount();
  gAfter = gBefore + kOutputs;
  std::atomic<bool> done{false};
  const pthread_t committer = pthread_self();
  std::thread sender([&] {  // signals the committing thread without pause until it is done
    while (!done.load()) pthread_kill(committer, SIGUSR1);
  });
  vox::commitAll(all);
  done = true;
  sender.join();
  sigaction(SIGUSR1, &old, nullptr);
  EXPECT_GT(gDeferred.load(), 0) << "no signal arrived during the renames: the test proves nothing";
  EXPECT_EQ(gSeenMidCommit.load(), 0) << "a handler ran between two renames";
  EXPECT_EQ(vox::committedOutputCount(), gAfter.load());
  for (int i = 0; i < kOutputs; ++i) EXPECT_EQ(vox::readFileBytes(dir.file("out_" + std::to_string(i) + ".bin")), "new");
}

}  // namespace
