#include "libvox/core/memory_budget.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>

#include "libvox/core/error.h"

namespace vox {

void MemoryEstimate::add(std::string name, uint64_t bytes) { parts.push_back({std::move(name), bytes}); }

void MemoryEstimate::add(std::string name, double bytes) {
  const double b = std::isfinite(bytes) ? std::clamp(bytes, 0.0, 9.2e18) : 9.2e18;
  add(std::move(name), uint64_t(std::llround(b)));
}

uint64_t MemoryEstimate::bytes() const {
  uint64_t sum = 0;
  for (const MemoryPart& p : parts) sum = sum + p.bytes < sum ? UINT64_MAX : sum + p.bytes;
  return sum;
}

std::string MemoryEstimate::describe() const {
  const uint64_t total = bytes();
  std::vector<MemoryPart> sorted = parts;
  std::stable_sort(sorted.begin(), sorted.end(), [](const MemoryPart& a, const MemoryPart& b) { return a.bytes > b.bytes; });
  std::string s = formatBytes(total), inner;
  for (const MemoryPart& p : sorted) {
    if (p.bytes == 0 || double(p.bytes) < 0.01 * double(total)) continue;
    inner += (inner.empty() ? "" : ", ") + p.name + " " + formatBytes(p.bytes);
  }
  return inner.empty() ? s : s + " (" + inner + ")";
}

namespace {

/// The first unsigned number in a file ("max" and unreadable files: 0).
uint64_t readNumber(const char* path) {
  std::ifstream in(path);
  std::string word;
  if (!(in >> word) || word.empty() || word[0] < '0' || word[0] > '9') return 0;
  try {
    return std::stoull(word);
  } catch (...) {
    return 0;
  }
}

/// This process's cgroup memory limit (v2, then v1); 0 when none.
uint64_t cgroupLimit() {
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  uint64_t best = 0;
  auto consider = [&best](uint64_t v) {
    // v1 reports "no limit" as a huge number (PAGE_COUNTER_MAX pages): ignore those.
    if (v > 0 && v < (uint64_t(1) << 60) && (best == 0 || v < best)) best = v;
  };
  while (std::getline(in, line)) {
    // v2: "0::/path"; v1: "N:memory:/path" (or a comma list containing memory).
    const size_t a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const std::string controllers = line.substr(a + 1, b - a - 1), path = line.substr(b + 1);
    if (controllers.empty()) {
      // Walk up from the process's cgroup: a parent's limit binds too.
      for (std::string p = path;; p = p.substr(0, p.find_last_of('/'))) {
        consider(readNumber(("/sys/fs/cgroup" + p + "/memory.max").c_str()));
        if (p.empty() || p == "/") break;
      }
    } else if (("," + controllers + ",").find(",memory,") != std::string::npos) {
      consider(readNumber(("/sys/fs/cgroup/memory" + path + "/memory.limit_in_bytes").c_str()));
      consider(readNumber("/sys/fs/cgroup/memory/memory.limit_in_bytes"));
    }
  }
  return best;
}

uint64_t memTotal() {
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  uint64_t value = 0;
  while (in >> key >> value) {
    std::getline(in, unit);
    if (key == "MemTotal:") return value * 1024;
  }
  return 0;
}

}  // namespace

PhysicalMemory physicalMemory() {
  static std::once_flag once;
  static PhysicalMemory cached;
  std::call_once(once, [] {
    const uint64_t total = memTotal(), cgroup = cgroupLimit();
    if (cgroup > 0 && (total == 0 || cgroup < total)) cached = {cgroup, "the cgroup's memory limit"};
    else cached = {total, "physical memory"};
  });
  return cached;
}

MemoryLimit defaultMemoryLimit() {
  const PhysicalMemory m = physicalMemory();
  if (m.bytes == 0) return {0, "none (physical memory unknown)"};
  const uint64_t bytes = uint64_t(double(m.bytes) * kDefaultMemoryFraction);
  return {bytes, formatBytes(bytes) + " (" + std::to_string(int(std::lround(kDefaultMemoryFraction * 100))) + "% of " +
                     formatBytes(m.bytes) + " " + m.source + ")"};
}

uint64_t parseByteSize(const std::string& text, const std::string& option) {
  auto bad = [&]() -> uint64_t {
    throwUsage(option + " " + text + ": expected a size such as 12G, 500M, 64K or a number of bytes (0 = no limit)");
  };
  size_t i = 0;
  while (i < text.size() && (std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '.')) ++i;
  if (i == 0) return bad();
  double number = 0;
  try {
    size_t used = 0;
    number = std::stod(text.substr(0, i), &used);
    if (used != i) return bad();
  } catch (...) {
    return bad();
  }
  std::string unit = text.substr(i);
  std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return char(std::toupper(c)); });
  if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();                      // "GB", "GIB" -> "G", "GI"
  if (unit.size() == 2 && unit.back() == 'I') unit.pop_back();                     // "GI" -> "G"
  double scale = 1;
  if (unit == "") scale = 1;
  else if (unit == "K") scale = 1024.0;
  else if (unit == "M") scale = 1024.0 * 1024;
  else if (unit == "G") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
  else return bad();
  const double bytes = number * scale;
  if (!std::isfinite(bytes) || bytes >= 9.2e18) return bad();
  return uint64_t(std::llround(bytes));
}

MemoryLimit memoryLimitFrom(const std::string& text, const std::string& option) {
  if (text.empty()) return defaultMemoryLimit();
  const uint64_t bytes = parseByteSize(text, option);
  if (bytes == 0) return {0, "none (" + option + " 0)"};
  return {bytes, formatBytes(bytes) + " (" + option + ")"};
}

std::string formatBytes(uint64_t bytes) {
  if (bytes < 1024) return std::to_string(bytes) + (bytes == 1 ? " byte" : " bytes");
  static const char* const kUnits[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double v = double(bytes) / 1024;
  int u = 0;
  while (v >= 1024 && u < 5) v /= 1024, ++u;
  char buf[32];
  std::snprintf(buf, sizeof buf, v >= 100 ? "%.0f %s" : v >= 10 ? "%.1f %s" : "%.2f %s", v, kUnits[u]);
  return buf;
}

void checkMemory(const MemoryEstimate& estimate, const MemoryLimit& limit, const std::string& what,
                 const std::string& suggestion, const std::string& limitOption) {
  if (limit.unlimited() || estimate.bytes() <= limit.bytes) return;
  std::string m = what + " needs about " + estimate.describe() + " but the memory limit is " + limit.description;
  m += suggestion.empty() ? "; raise " + limitOption + " (0 = no limit) if the machine has the memory"
                          : ": " + suggestion + ", or raise " + limitOption + " (0 = no limit)";
  throw Error(ErrorKind::Resource, m);
}

namespace {
std::mutex gLimitMutex;
MemoryLimit gProcessLimit;
std::string gLimitOption = "the memory limit";
std::vector<CheckedEstimate> gChecked;
}  // namespace

std::vector<CheckedEstimate> checkedEstimates() {
  std::lock_guard<std::mutex> lock(gLimitMutex);
  return gChecked;
}

void setProcessMemoryLimit(const MemoryLimit& limit, const std::string& option) {
  std::lock_guard<std::mutex> lock(gLimitMutex);
  gProcessLimit = limit;
  gLimitOption = option;
}

MemoryLimit processMemoryLimit() {
  std::lock_guard<std::mutex> lock(gLimitMutex);
  return gProcessLimit;
}

void checkProcessMemory(const MemoryEstimate& estimate, const std::string& what, const std::string& suggestion) {
  std::string option;
  MemoryLimit limit;
  {
    std::lock_guard<std::mutex> lock(gLimitMutex);
    option = gLimitOption;
    limit = gProcessLimit;
    gChecked.push_back({what, estimate});
  }
  checkMemory(estimate, limit, what, suggestion, option);
}

uint64_t largestFitting(uint64_t lo, uint64_t hi, uint64_t limit, const std::function<uint64_t(uint64_t)>& bytesAt) {
  if (lo > hi || bytesAt(lo) > limit) return 0;
  while (lo < hi) {
    const uint64_t mid = lo + (hi - lo + 1) / 2;
    if (bytesAt(mid) <= limit) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

namespace {

/// A "Name:   123 kB" line of /proc/self/status, in bytes; 0 when absent.
uint64_t statusBytes(const std::string& name) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(name, 0) == 0) {
      std::istringstream s(line.substr(name.size()));
      uint64_t kb = 0;
      s >> kb;
      return kb * 1024;
    }
  return 0;
}

}  // namespace

uint64_t residentBytesNow() { return statusBytes("VmRSS:"); }

uint64_t peakResidentBytesSoFar() { return statusBytes("VmHWM:"); }

}  // namespace vox
