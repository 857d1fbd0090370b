// The one memory guard: what a run will need, what the machine allows, and a
// refusal before the work when the first exceeds the second.
//
// Every command estimates its peak resident memory from what it knows before
// the work (bounds, surface area, occupied voxels, resolution; the estimators
// live beside the code whose data structures they model) and calls
// checkMemory(). A request over the limit is refused with vox::Error
// (ErrorKind::Resource, exit 4) whose message gives the estimate and its
// largest parts, the limit and where it comes from, and a setting that would
// fit (computed by the same estimator, never guessed).
//
// Units: bytes throughout. The limit defaults to kDefaultMemoryFraction of the
// physical memory available to the process (MemTotal of /proc/meminfo, or the
// cgroup's memory limit when that is smaller); 0 means "no limit".
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace vox {

/// The share of physical memory a run may plan to use unless told otherwise.
/// Not 100%: the estimate is within 2x of the peak, not exact, and the rest of
/// the machine (page cache, other processes) needs room too.
inline constexpr double kDefaultMemoryFraction = 0.8;

/// What glibc's malloc adds to each heap block (its header and rounding),
/// about: the estimates count it once per block they allocate.
inline constexpr double kMallocBlockBytes = 16;

/// One part of an estimate ("vote blocks", "mesh"...), in bytes.
struct MemoryPart {
  std::string name;
  uint64_t bytes = 0;
};

/// A run's estimated peak resident memory, as the sum of named parts.
struct MemoryEstimate {
  std::vector<MemoryPart> parts;

  void add(std::string name, uint64_t bytes);
  void add(std::string name, double bytes);  // rounds; clamps to [0, 2^63]
  uint64_t bytes() const;                    // saturating sum of the parts
  /// "31.2 GiB (vote blocks 24 GiB, mesh 6 GiB, ...)": the largest parts first,
  /// parts under 1% of the total left out.
  std::string describe() const;
};

/// The physical memory this process can use and where the figure comes from.
struct PhysicalMemory {
  uint64_t bytes = 0;  // 0 when unknown
  std::string source;  // "physical memory" or "the cgroup's memory limit"
};

/// MemTotal of /proc/meminfo, or the cgroup v2 memory.max / v1
/// memory.limit_in_bytes of this process when smaller. Cached after the first call.
PhysicalMemory physicalMemory();

/// The limit a run plans against.
struct MemoryLimit {
  uint64_t bytes = 0;       // 0 = no limit
  std::string description;  // "19.2 GiB (80% of 24 GiB physical memory)"
  bool unlimited() const { return bytes == 0; }
};

/// kDefaultMemoryFraction of physicalMemory() (no limit when that is unknown).
MemoryLimit defaultMemoryLimit();

/// A size as users write it: "12G", "500M", "64k", "1.5GiB", "123456" (bytes);
/// K/M/G/T are powers of 1024 (with or without "iB"/"B"); "0" = no limit.
/// Throws vox::Error (Usage) naming `option` on anything else.
uint64_t parseByteSize(const std::string& text, const std::string& option);

/// The limit from an option's text: empty = defaultMemoryLimit(), else parseByteSize().
MemoryLimit memoryLimitFrom(const std::string& text, const std::string& option);

/// "31.2 GiB", "512 MiB", "900 KiB", "12 bytes": three significant digits.
std::string formatBytes(uint64_t bytes);

/// Throws vox::Error (ErrorKind::Resource) when `estimate` exceeds `limit`:
/// "<what> needs about <estimate> but the limit is <limit>: <suggestion>".
/// `suggestion` says what would fit (may be empty). No-op when unlimited.
void checkMemory(const MemoryEstimate& estimate, const MemoryLimit& limit, const std::string& what,
                 const std::string& suggestion, const std::string& limitOption);

/// The limit of this process's run: set by the CLI from --max-memory before
/// the work (none until then, so library users are never refused). Readers that
/// are about to allocate in proportion to a file (the scene and pyramid
/// readers) check against it, so every command is guarded at every read.
void setProcessMemoryLimit(const MemoryLimit& limit, const std::string& option);
MemoryLimit processMemoryLimit();
/// checkMemory() against processMemoryLimit(), after recording the estimate
/// (checkedEstimates(): the CLI puts them in --report).
void checkProcessMemory(const MemoryEstimate& estimate, const std::string& what, const std::string& suggestion = "");

/// Every estimate checkProcessMemory() saw in this process, in order.
struct CheckedEstimate {
  std::string what;
  MemoryEstimate estimate;
};
std::vector<CheckedEstimate> checkedEstimates();

/// The largest n in [lo, hi] with bytesAt(n) <= limit, assuming bytesAt grows
/// with n; 0 when even lo does not fit. Binary search: O(log(hi - lo)) calls.
uint64_t largestFitting(uint64_t lo, uint64_t hi, uint64_t limit, const std::function<uint64_t(uint64_t)>& bytesAt);

/// The bytes a suggested setting ("--res 1931 would need about ...") is fitted
/// under: 1/32 below `limit`, so that the suggestion still fits when the
/// command is run again with it (the resident part of an estimate moves by a
/// few MB from run to run).
inline uint64_t suggestionBudget(uint64_t limit) { return limit - limit / 32; }

/// Resident memory of this process now (VmRSS of /proc/self/status), 0 when unknown.
uint64_t residentBytesNow();

/// The largest resident memory this process has had so far (VmHWM of
/// /proc/self/status: what /usr/bin/time and getrusage report as its peak),
/// 0 when unknown. An estimate made after a step that peaked and freed (a
/// mesh file's parse) is never below it.
uint64_t peakResidentBytesSoFar();

}  // namespace vox
