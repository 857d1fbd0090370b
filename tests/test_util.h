// Helpers shared by the unit tests.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "libvox/core/error.h"

namespace voxtest {

/// The checkout's root: fixtures, regression inputs and docs the tests read.
std::string sourceDir();

/// ../shared/data beside the checkout. It may be absent: tests that need it
/// skip with a message.
std::string sharedDataDir();

/// A fresh directory under the system temp dir, removed with its content.
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "voxtest-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

/// Runs `fn`, expects a vox::Error of `kind` whose message contains every `needle`.
template <typename Fn>
::testing::AssertionResult throwsVoxError(Fn&& fn, vox::ErrorKind kind, std::initializer_list<std::string> needles) {
  try {
    fn();
  } catch (const vox::Error& e) {
    if (e.kind != kind) return ::testing::AssertionFailure() << "wrong kind for: " << e.what();
    for (const std::string& n : needles)
      if (std::string(e.what()).find(n) == std::string::npos)
        return ::testing::AssertionFailure() << "message '" << e.what() << "' lacks '" << n << "'";
    return ::testing::AssertionSuccess();
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "not a vox::Error: " << e.what();
  }
  return ::testing::AssertionFailure() << "no exception";
}

/// The setting named by the vox::Error `fn` throws (None when it throws none).
template <typename Fn>
vox::Setting settingOfError(Fn&& fn) {
  try {
    fn();
  } catch (const vox::Error& e) {
    return e.setting;
  }
  return vox::Setting::None;
}

}  // namespace voxtest
