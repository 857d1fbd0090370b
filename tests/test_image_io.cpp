// PNG and EXR round trips for every sample type the tool writes, text metadata,
// determinism, and refusal of corrupt files.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <Imath/half.h>

#include "formats/core/file_util.h"
#include "formats/image/image.h"
#include "test_util.h"

using namespace vox;

namespace {
Image pattern(uint32_t w, uint32_t h, uint32_t c, SampleType t) {
  Image img(w, h, c, t);
  uint32_t seed = 12345;
  for (uint8_t& b : img.pixels) {
    seed = seed * 1664525u + 1013904223u;
    b = uint8_t(seed >> 24);
  }
  if (t == SampleType::F16 || t == SampleType::F32) {
    // Exact small integers and their neighbours, as atlases hold.
    for (size_t i = 0; i < size_t(w) * h * c; ++i) {
      const float v = float(i % 2049);
      if (t == SampleType::F16) {
        const uint16_t bits = Imath::half(v).bits();
        std::memcpy(img.pixels.data() + 2 * i, &bits, 2);
      } else {
        std::memcpy(img.pixels.data() + 4 * i, &v, 4);
      }
    }
  }
  img.text = {{"vox:layout", "{\"dims\":[3,5,7]}"}, {"Software", "vox test"}};
  return img;
}
}  // namespace

TEST(ImageIo, PngRoundTripsEveryShape) {
  voxtest::TempDir dir;
  for (SampleType t : {SampleType::U8, SampleType::U16})
    for (uint32_t c = 1; c <= 4; ++c) {
      const Image img = pattern(37, 11, c, t);
      std::string name = std::to_string(c);
      name.append(sampleTypeName(t)).append(".png");
      const std::string path = dir.file(name);
      writePng(img, path);
      EXPECT_TRUE(isPngFile(path));
      const Image back = readPng(path);
      EXPECT_EQ(back.width, 37u);
      EXPECT_EQ(back.height, 11u);
      EXPECT_EQ(back.channels, c);
      EXPECT_EQ(back.type, t);
      EXPECT_TRUE(back.pixels == img.pixels) << "channels " << c << " " << sampleTypeName(t);
      EXPECT_EQ(back.textValue("vox:layout"), "{\"dims\":[3,5,7]}");
    }
}

TEST(ImageIo, ParallelPngRoundTripsAndDoesNotDependOnThreads) {
  // Heights around the slice sizes (64 rows, at most 16 slices), every shape,
  // several zlib levels; libpng must read every file back to the same pixels.
  voxtest::TempDir dir;
  for (uint32_t h : {1u, 63u, 64u, 129u, 1100u})
    for (SampleType t : {SampleType::U8, SampleType::U16})
      for (uint32_t c = 1; c <= 4; ++c)
        for (int level : {1, 6, 9}) {
          if (h == 1100 && (c != 4 || level != 6)) continue;
          Image img = pattern(h == 1100 ? 211 : 37, h, c, t);
          for (size_t i = 0; i < img.pixels.size() / 3; ++i) img.pixels[i] = 0;  // runs, as renders have
          const std::string p1 = dir.file("t1.png"), p4 = dir.file("t4.png");
          writePngParallel(img, p1, level, 1);
          writePngParallel(img, p4, level, 4);
          ASSERT_EQ(readFileBytes(p1), readFileBytes(p4)) << "h " << h << " c " << c << " " << sampleTypeName(t);
          const Image back = readPng(p4);
          ASSERT_EQ(back.width, img.width);
          ASSERT_EQ(back.height, h);
          ASSERT_EQ(back.channels, c);
          ASSERT_EQ(back.type, t);
          ASSERT_TRUE(back.pixels == img.pixels) << "h " << h << " c " << c << " " << sampleTypeName(t) << " level " << level;
          EXPECT_EQ(back.textValue("vox:layout"), "{\"dims\":[3,5,7]}");
        }
}

TEST(ImageIo, PngWritersRefuseSidesPastLibpngsLimitBeforeWriting) {
  // libpng reads (and writes) sides up to kMaxPngSide; the parallel writer,
  // which does not use libpng, keeps the same limit itself, naming the output.
  voxtest::TempDir dir;
  Image edge(kMaxPngSide, 1, 1, SampleType::U8);
  writePngParallel(edge, dir.file("edge.png"), kDefaultPngZlibLevel, 2);
  EXPECT_EQ(readPng(dir.file("edge.png")).width, kMaxPngSide) << "the limit itself is written and read back";
  const std::string past = std::to_string(kMaxPngSide + 1), limit = std::to_string(kMaxPngSide);
  for (const bool wide : {true, false}) {
    const Image big = wide ? Image(kMaxPngSide + 1, 1, 1, SampleType::U8) : Image(1, kMaxPngSide + 1, 1, SampleType::U8);
    const std::string side = past + (wide ? " pixels wide" : " pixels high");
    AtomicOutput out(dir.file("big.png"));  // messages name the output, not its temporary
    const std::vector<std::function<void()>> writers = {
        [&] { writePngParallel(big, out.tempPath(), kDefaultPngZlibLevel, 2); },
        [&] { writeIndexedPngParallel(big, {{0, 0, 0}}, out.tempPath(), kDefaultPngZlibLevel, 2); },
        [&] { writePng(big, out.tempPath()); },
    };
    for (size_t w = 0; w < writers.size(); ++w) {
      EXPECT_TRUE(voxtest::throwsVoxError(writers[w], ErrorKind::Usage, {dir.file("big.png") + ": ", side, limit}))
          << "writer " << w << ", " << side;
      EXPECT_FALSE(std::filesystem::exists(out.tempPath())) << "writer " << w << " wrote before refusing " << side;
    }
  }
}

TEST(ImageIo, PngIsByteIdenticalForIdenticalInput) {
  voxtest::TempDir dir;
  const Image img = pattern(300, 200, 4, SampleType::U8);
  writePng(img, dir.file("a.png"));
  writePng(img, dir.file("b.png"));
  EXPECT_EQ(readFileBytes(dir.file("a.png")), readFileBytes(dir.file("b.png")));
}

TEST(ImageIo, ExrRoundTripsUintHalfFloat) {
  voxtest::TempDir dir;
  for (SampleType t : {SampleType::U32, SampleType::F16, SampleType::F32})
    for (uint32_t c : {1u, 4u}) {
      const Image img = pattern(19, 23, c, t);
      const std::string path = dir.file(std::string("e") + sampleTypeName(t) + std::to_string(c) + ".exr");
      writeExr(img, path);
      EXPECT_TRUE(isExrFile(path));
      const Image back = readExr(path);
      EXPECT_EQ(back.type, t);
      EXPECT_EQ(back.channels, c);
      EXPECT_TRUE(back.pixels == img.pixels) << sampleTypeName(t);
      EXPECT_EQ(back.textValue("vox:layout"), "{\"dims\":[3,5,7]}");
    }
}

TEST(ImageIo, CorruptFilesAreBadInput) {
  voxtest::TempDir dir;
  writePng(pattern(64, 64, 4, SampleType::U8), dir.file("good.png"));
  const std::string bytes = readFileBytes(dir.file("good.png"));
  for (size_t n : {size_t(0), size_t(8), size_t(30), bytes.size() / 2, bytes.size() - 1}) {
    voxtest::writeText(dir.file("cut.png"), bytes.substr(0, n));
    EXPECT_TRUE(voxtest::throwsVoxError([&] { readPng(dir.file("cut.png")); }, ErrorKind::BadInput, {"cut.png"}))
        << n;
  }
  writeExr(pattern(64, 64, 4, SampleType::F32), dir.file("good.exr"));
  const std::string exr = readFileBytes(dir.file("good.exr"));
  for (size_t n : {size_t(3), size_t(100), exr.size() / 2}) {
    voxtest::writeText(dir.file("cut.exr"), exr.substr(0, n));
    EXPECT_TRUE(voxtest::throwsVoxError([&] { readExr(dir.file("cut.exr")); }, ErrorKind::BadInput, {"cut.exr"}))
        << n;
  }
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readPng(dir.file("none.png")); }, ErrorKind::BadInput, {"none.png"}));
}

namespace {
uint64_t virtualMemoryBytes() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmSize:", 0) == 0) return std::stoull(line.substr(7)) * 1024;
  return 0;
}
}  // namespace

// OpenEXR allocates an attribute at the size the file claims before reading
// it, and reads a box2i as 16 bytes whatever size is declared: a 1 KB file
// whose displayWindow declared 126 bytes led OpenEXR's header parse into an
// attribute of 1.6 GB. It must be refused without that allocation. The reader runs in a child process whose address space is capped at 256 MB
// above what it already uses, where a 1.6 GB allocation fails (bad_alloc)
// instead of being refused by its size.
TEST(ImageIo, ExrHeaderOpenExrWouldReadAsAHugeAttributeIsRefusedWithoutAllocatingIt) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "an address-space cap does not work under AddressSanitizer's shadow memory";
#else
  // Found by the fuzzer (from an atlas written by vox).
  const std::string path =
      voxtest::sourceDir() + "/tests/fuzz/regressions/exr/box2i_declared_126_bytes_then_1_6GB_attribute.exr";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const rlim_t cap = virtualMemoryBytes() + (rlim_t(256) << 20);
    const rlimit limit{cap, cap};
    setrlimit(RLIMIT_AS, &limit);
    try {
      readExr(path);
      _exit(3);  // read as an image: wrong
    } catch (const Error& e) {
      const std::string what = e.what();
      if (e.kind == ErrorKind::BadInput && what.find("bad_alloc") == std::string::npos) _exit(0);
      std::fprintf(stderr, "refused with: %s\n", what.c_str());
      _exit(4);
    } catch (...) {
      _exit(5);
    }
  }
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "the reader was killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "3: read as an image, 4: not a clean refusal (or bad_alloc), 5: other exception";
  EXPECT_TRUE(voxtest::throwsVoxError([&] { readExr(path); }, ErrorKind::BadInput,
                                      {"box2i_declared_126_bytes_then_1_6GB_attribute.exr", "corrupt or truncated EXR",
                                       "'displayWindow' (box2i) at byte 237 declares 126 bytes; a box2i has 16"}));
#endif
}

TEST(FileUtil, UncommittedTemporariesAreRemovedOnRequest) {
  voxtest::TempDir dir;
  vox::AtomicOutput kept(dir.file("kept.bin"));
  vox::writeFileBytes(kept.tempPath(), "done");
  kept.commit();
  vox::AtomicOutput open(dir.file("open.bin"));
  vox::writeFileBytes(open.tempPath(), "half");
  vox::removeUncommittedOutputs();  // what the CLI's signal handler does
  EXPECT_FALSE(std::filesystem::exists(open.tempPath()));
  EXPECT_EQ(vox::readFileBytes(dir.file("kept.bin")), "done");
}

TEST(FileUtil, TemporariesOfDeadRunsAreRemovedByTheNextRun) {
  // A process reads a directory for stale temporaries at its first output
  // there: the probe that gives this host's tag writes elsewhere.
  voxtest::TempDir dir, probeDir;
  const pid_t child = fork();
  if (child == 0) _exit(0);
  ASSERT_GT(child, 0);
  waitpid(child, nullptr, 0);  // a pid that no longer runs
  std::string stale, alive, other;
  {
    vox::AtomicOutput probe(probeDir.file("scene.vdb"));  // its name gives this host's tag
    const std::string t = probe.tempPath();
    const size_t pidAt = t.find('-', t.rfind(".tmp-") + 5) + 1;
    const std::string prefix = t.substr(0, pidAt);
    const std::string inDir = dir.file(std::filesystem::path(prefix).filename().string());
    stale = inDir + std::to_string(child) + "-0";
    alive = inDir + "1-0";  // init: alive, never ours to remove
    other = dir.file(".scene.vdb.tmp-00000000-" + std::to_string(child) + "-0");
  }
  if (stale.find(".tmp-00000000-") != std::string::npos)
    GTEST_SKIP() << "this host's name hashes to 00000000";
  for (const std::string& f : {stale, alive, other}) voxtest::writeText(f, "x");
  vox::AtomicOutput next(dir.file("scene.vdb"));
  EXPECT_FALSE(std::filesystem::exists(stale)) << "a dead run's temporary was kept";
  EXPECT_TRUE(std::filesystem::exists(alive)) << "a live process's temporary was removed";
  EXPECT_TRUE(std::filesystem::exists(other)) << "another host's temporary was removed";
}

TEST(FileUtil, NamesNearTheLimitGetShortTemporaries) {
  // A 250-byte name is valid (NAME_MAX is 255), but ".NAME.tmp-HOST-PID-N" is
  // not: its temporary takes a prefix and a hash of the name instead.
  voxtest::TempDir dir;
  const std::string name = std::string(246, 'n') + ".vdb", other = std::string(245, 'n') + "x.vdb";
  std::string firstTemp;
  {
    vox::AtomicOutput out(dir.file(name));
    firstTemp = out.tempPath();
    EXPECT_LE(std::filesystem::path(out.tempPath()).filename().string().size(), 255u);
    EXPECT_EQ(vox::outputName(out.tempPath()), dir.file(name)) << "messages name the output";
    vox::writeFileBytes(out.tempPath(), "scene");
    out.commit();
  }
  EXPECT_EQ(vox::readFileBytes(dir.file(name)), "scene");
  vox::AtomicOutput second(dir.file(other));  // same first bytes, another name: another temporary
  const std::string a = std::filesystem::path(second.tempPath()).filename().string();
  const std::string b = std::filesystem::path(firstTemp).filename().string();
  EXPECT_NE(a.substr(0, a.rfind(".tmp-")), b.substr(0, b.rfind(".tmp-"))) << "the hash tells them apart";
  // A dead run's temporary of the long name is found and removed like any
  // other (in a directory this process has not written to yet: it reads each
  // once, at its first output there).
  voxtest::TempDir next;
  const pid_t child = fork();
  if (child == 0) _exit(0);
  ASSERT_GT(child, 0);
  waitpid(child, nullptr, 0);
  const std::string firstName = std::filesystem::path(firstTemp).filename().string();
  const size_t pidAt = firstName.find('-', firstName.rfind(".tmp-") + 5) + 1;
  const std::string stale = next.file(firstName.substr(0, pidAt) + std::to_string(child) + "-0");
  voxtest::writeText(stale, "x");
  vox::AtomicOutput third(next.file(name));
  EXPECT_FALSE(std::filesystem::exists(stale)) << "a dead run's temporary of a long name was kept";
}

TEST(FileUtil, MessagesNameTheOutputNotItsTemporary) {
  vox::AtomicOutput out("dir/keep.glb");
  const std::string t = out.tempPath();
  EXPECT_EQ(vox::withOutputNames(t + ": cannot write: File too large"), "dir/keep.glb: cannot write: File too large");
  EXPECT_EQ(vox::withOutputNames("writing '" + t + "' failed (" + t + ")"),
            "writing 'dir/keep.glb' failed (dir/keep.glb)");
  EXPECT_EQ(vox::withOutputNames("plain message, no .tmp-x here"), "plain message, no .tmp-x here");
  EXPECT_EQ(vox::withOutputNames("a/.x.tmp-0123abcd-12-3: full"), "a/x: full");
}

TEST(FileUtil, OutputNameMapsTemporariesToTheirOutput) {
  vox::AtomicOutput out("dir/scene.vdb");
  EXPECT_EQ(vox::outputName(out.tempPath()), "dir/scene.vdb");
  EXPECT_EQ(vox::outputName("dir/scene.vdb"), "dir/scene.vdb");
  EXPECT_EQ(vox::outputName(".hidden.tmp"), ".hidden.tmp");
  EXPECT_EQ(vox::outputName("a/.x.tmp12.y"), "a/.x.tmp12.y");
  EXPECT_EQ(vox::outputName("a/.x.tmp-0123abcd-12-3"), "a/x");
  EXPECT_EQ(vox::outputName("a/.x.tmp-0123abcd-12"), "a/.x.tmp-0123abcd-12");
  EXPECT_EQ(vox::outputName("a/.x.tmp-0123ABCD-12-3"), "a/.x.tmp-0123ABCD-12-3");
}
