// vox build-atlas SCENE -o DIR: the scene's atlases and occupancy bitmaps at
// their voxel<->texel addresses (the UVW atlas layout, formats/image/ATLAS.md),
// and only what is asked.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <filesystem>
#include <mutex>

#include "formats/core/file_util.h"
#include "formats/image/atlas_meta.h"
#include "formats/image/atlas_preview.h"
#include "formats/image/image.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/core/atlas_content.h"
#include "libvox/core/bitmap_packing.h"
#include "libvox/core/error.h"
#include "libvox/core/memory_budget.h"
#include "libvox/core/parallel.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/core/texel_formats.h"
#include "libvox/scene/scene_pieces.h"
#include "tools/cli/alloc_tuning.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/enum_option.h"

namespace voxcli {

namespace {

namespace fs = std::filesystem;

struct BuildAtlasOptions {
  std::string scene, outDir, stem;
  bool summary = false, occupancy = false, occupancy2 = false, identity = false, color = false, votes = false,
       all = false, preview = false;
  vox::TexelFormat identityFormat = vox::TexelFormat::Rgba8;
  CLI::Option* identityFormatOption = nullptr;  // given: identityFormat; else the narrowest exact format
  uint32_t tilesPerRow = 0, maxSide = vox::kDefaultAtlasMaxSide;
  int compression = vox::kDefaultPngZlibLevel;
  CommonOptions common;
};

/// One output file: an image per (content, class, layer).
struct Output {
  vox::AtlasImageInfo info;
  vox::Image image;
  std::string path, tempPath;
  std::string previewTempPath;  // --preview: where its preview goes
  bool exr = false;
};

/// Refuses, before the work, an output directory that cannot be made because
/// something other than a directory stands where it or a parent would be
/// (mkdir would say only "Not a directory").
void checkCanCreate(const std::string& path) {
  const fs::path want = fs::path(path).lexically_normal();
  for (fs::path p = want; !p.empty(); p = p.parent_path()) {
    std::error_code ec;
    const fs::file_status st = fs::status(p, ec);
    if (fs::exists(st)) {
      if (fs::is_directory(st)) return;
      const std::string what = fs::is_regular_file(st) ? "a file" : "not a directory";
      throw vox::Error(vox::ErrorKind::Io, path + ": cannot create the output directory: " +
                                               (p == want ? "it is " + what : p.string() + " is " + what) +
                                               "; give -o a directory (it is created if missing)");
    }
    if (p == p.parent_path()) break;
  }
}

int runBuildAtlas(const BuildAtlasOptions& o) {
  // The levels of -o this run makes: removed again (while empty) when the run
  // fails or is interrupted. Declared before the Run, so it is destroyed after
  // the Run has removed its temporaries.
  vox::CreatedDirectories outDir;
  Run run("build-atlas", o.common);
  if (!o.stem.empty() && (o.stem.find('/') != std::string::npos || o.stem == "." || o.stem == ".."))
    throw vox::Error(vox::ErrorKind::Usage, "--stem " + o.stem + ": a file name stem, without '/', is expected; "
                                            "choose the directory with -o");

  if (o.outDir.empty())
    throw vox::Error(vox::ErrorKind::Usage, "--output '': an empty path; give the output directory (created if missing)");
  if (o.outDir == "-")
    throw vox::Error(vox::ErrorKind::Usage, "-o -: build-atlas writes a directory of files, never standard output; "
                                            "give the output directory (created if missing)");
  checkCanCreate(o.outDir);
  // --format chooses the identity atlas's texel format; the other contents
  // have one format each, so it would be ignored (--summary --format rgba16
  // wrote rgba8).
  if (o.identityFormatOption->count() > 0 && !o.identity && !o.all)
    throw vox::Error(vox::ErrorKind::Usage, "--format applies to the identity atlas (--identity or --all); the "
                                            "summary, colour, votes and bitmaps are written in their own formats");

  // libpng refuses to write a PNG side past kMaxPngSide, and the parallel
  // encoder's wider files could not be read back: a larger side is refused
  // here, before the work, rather than at the write (one limit for every
  // file, EXR too, so the layout does not depend on the contents asked for).
  if (o.maxSide > vox::kMaxPngSide)
    throw vox::Error(vox::ErrorKind::Usage, "--max-side " + std::to_string(o.maxSide) + ": past " +
                                                std::to_string(vox::kMaxPngSide) +
                                                ", the largest PNG side vox writes and reads back (libpng's limit); "
                                                "give --max-side " + std::to_string(vox::kMaxPngSide) + " or less");

  // The images are tens of MB of fresh heap filled once: huge pages spare the
  // page faults (alloc_tuning.h).
  tuneAllocatorForShortRun();
  run.phase("read");
  run.input(o.scene);
  const vox::Scene scene = vox::readSceneVdb(o.scene);
  const vox::SceneHeader& h = scene.header();

  // What to write: the flags given, or summary + occupancy.
  const bool any = o.summary || o.occupancy || o.occupancy2 || o.identity || o.color || o.votes || o.all;
  const bool wSummary = o.all || o.summary || !any, wOcc = o.all || o.occupancy || !any;
  const bool wOcc2 = o.all || o.occupancy2, wIdentity = o.all || o.identity, wVotes = o.all || o.votes;
  const bool wColor = (o.all && scene.hasColor()) || o.color;
  if (o.color && !scene.hasColor())
    throw vox::Error(vox::ErrorKind::Usage, o.scene + ": the scene has no colour, so there is no colour atlas to write");

  const vox::AtlasLayout L = vox::AtlasLayout::make(h.dims, o.tilesPerRow, o.maxSide);
  const uint64_t maxCoord = uint64_t(h.dims.maxAxis()) - 1;
  vox::TexelFormat idFormat = vox::narrowestExactFormat(maxCoord);
  if (o.identityFormatOption->count() > 0) {
    const vox::TexelFormat f = o.identityFormat;
    if (maxCoord > vox::documentedMaxExact(f))
      throw vox::Error(vox::ErrorKind::Usage,
                       std::string("--format ") + vox::texelFormatName(f) + " cannot hold coordinate " +
                           std::to_string(vox::documentedMaxExact(f) + 1) + " of " + vox::toString(h.dims) +
                           " exactly; " + vox::texelFormatName(vox::narrowestExactFormat(maxCoord)) + " would");
    idFormat = f;
  }
  const vox::SceneStats stats = scene.stats();
  const std::string stem = o.stem.empty() ? fs::path(o.scene).stem().string() : o.stem;

  // The directory is made only now that the input is known good, and removed
  // again (the levels this run made, while empty) if the run fails or is
  // interrupted after all.
  outDir.create(o.outDir);

  std::vector<Output> outs;
  auto add = [&](vox::AtlasContent content, const std::string& format, uint32_t channels, vox::SampleType type,
                 bool exr, uint8_t classId, uint32_t width) {
    for (uint32_t layer = 0; layer < L.layers; ++layer) {
      Output out;
      out.info = {L, content, format, layer, classId, o.scene};
      // Pixels are allocated layer by layer, when the layer is filled (below).
      out.image.width = width, out.image.height = L.height, out.image.channels = channels, out.image.type = type;
      out.exr = exr;
      std::string name = stem + "." + vox::atlasContentName(content);
      if (content == vox::AtlasContent::Votes) name += "." + std::to_string(classId);
      if (L.layers > 1) name += ".layer" + std::to_string(layer);
      out.path = (fs::path(o.outDir) / (name + (exr ? ".exr" : ".png"))).string();
      out.image.text = vox::atlasImageText(out.info);
      out.tempPath = run.output(out.path);
      if (o.preview) out.previewTempPath = run.output(vox::previewPath(out.path));
      outs.push_back(std::move(out));
    }
  };
  if (wSummary) add(vox::AtlasContent::Summary, "rgba8", 4, vox::SampleType::U8, false, 0, L.width);
  if (wIdentity) {
    const vox::SampleType t = idFormat == vox::TexelFormat::Rgba8    ? vox::SampleType::U8
                              : idFormat == vox::TexelFormat::Rgba16 ? vox::SampleType::U16
                              : idFormat == vox::TexelFormat::Rgba32ui ? vox::SampleType::U32
                              : idFormat == vox::TexelFormat::Rgba16f  ? vox::SampleType::F16
                                                                       : vox::SampleType::F32;
    add(vox::AtlasContent::Identity, vox::texelFormatName(idFormat), 4, t,
        t != vox::SampleType::U8 && t != vox::SampleType::U16, 0, L.width);
  }
  if (wColor) add(vox::AtlasContent::Color, "rgba8", 4, vox::SampleType::U8, false, 0, L.width);
  if (wVotes) {
    std::array<uint32_t, 256> maxVotesOf{};
    scene.forEachVoxel([&](const vox::VoxelView& v) {
      for (const vox::ClassVotes& c : v.votes) maxVotesOf[c.classId] = std::max(maxVotesOf[c.classId], c.votes);
    });
    for (const auto& pc : stats.perClass) {
      // Narrowest exact single channel for this class's largest count.
      const uint32_t maxVotes = maxVotesOf[pc.classId];
      if (maxVotes <= 255) add(vox::AtlasContent::Votes, "r8", 1, vox::SampleType::U8, false, pc.classId, L.width);
      else if (maxVotes <= 65535) add(vox::AtlasContent::Votes, "r16", 1, vox::SampleType::U16, false, pc.classId, L.width);
      else add(vox::AtlasContent::Votes, "r32ui", 1, vox::SampleType::U32, true, pc.classId, L.width);
    }
  }
  // The bitmaps, like the images, hold one layer at a time: their layout is
  // the atlas's with a single layer (a texel's layer is the one being filled).
  vox::AtlasLayout oneLayer = L;
  oneLayer.layers = 1;
  std::optional<vox::OccupancyBitmap> bits1, bits2;
  const uint32_t bits1Row = (L.width + 7) / 8, bits2Row = (L.width + 3) / 4;  // OccupancyBitmap::rowBytes()
  if (wOcc) add(vox::AtlasContent::Occupancy, "bitmap", 1, vox::SampleType::U8, false, 0, bits1Row);
  if (wOcc2) add(vox::AtlasContent::Occupancy2, "bitmap", 1, vox::SampleType::U8, false, 0, bits2Row);

  // Sparse scenes (far fewer occupied voxels than texels in a layer) are
  // written row by row from their occupied texels, sorted: memory in the
  // voxels, not the grid. The same bytes as the dense path. PNG data files
  // only: EXR files and --preview (drawn from the whole data image) take the
  // dense path, one layer at a time.
  const bool anyExr = std::any_of(outs.begin(), outs.end(), [](const Output& out) { return out.exr; });
  const bool stream =
      !o.preview && !anyExr && double(L.texelsPerLayer()) > 64.0 * double(std::max<uint64_t>(1, stats.occupied));

  // The memory guard: the scene, plus one layer of every image (and its
  // preview), or the sorted texels of the streamed files.
  {
    const uint64_t resident = vox::residentBytesNow();
    auto estimateFor = [&](const vox::AtlasLayout& layout) {
      vox::MemoryEstimate e;
      e.add("resident after reading the scene", resident);
      double images = 0, previews = 0, largest = 0;
      for (const Output& out : outs) {
        if (out.info.layer != 0) continue;
        const double texels = double(layout.texelsPerLayer());
        const double bytesPerTexel = out.image.width == L.width
                                         ? double(out.image.channels * vox::sampleBytes(out.image.type))
                                         : double(out.image.width) / double(L.width);  // bitmaps: bits per texel / 8
        images += texels * bytesPerTexel;
        largest = std::max(largest, texels * bytesPerTexel);
        // A preview: RGB (the summary's two panels side by side) plus its row slices.
        if (o.preview) previews += texels * (out.info.content == vox::AtlasContent::Summary ? 8.0 : 4.0);
      }
      if (stream) {
        // Per occupied voxel: a sorted (texel, value) record of 40 bytes per
        // image file, an 8-byte texel key for the bitmaps (+25%: vectors grow
        // by doubling); a row per encoder.
        size_t files = 0, images = 0;
        for (const Output& out : outs)
          if (out.info.layer == 0) {
            ++files;
            images += out.info.content != vox::AtlasContent::Occupancy &&
                      out.info.content != vox::AtlasContent::Occupancy2;
          }
        e.add("sorted texels", double(stats.occupied) * (double(images) * 40.0 + 8.0) * 1.25);
        e.add("rows", double(files) * double(L.width) * 8.0);
        return e;
      }
      e.add("atlas images (one layer)", images * 1.05);  // + the encoders' row buffers
      // Each worker filters a PNG row slice (at most 1/16 of an image) before deflating it.
      e.add("PNG slices being deflated", double(std::min(run.threads(), 16u)) * largest / 16);
      if (o.preview) e.add("previews (one layer)", previews);
      return e;
    };
    const vox::MemoryEstimate estimate = estimateFor(L);
    std::string suggestion;
    if (!run.memoryLimit().unlimited() && estimate.bytes() > run.memoryLimit().bytes) {
      // Smaller layers hold fewer texels: the largest --max-side that fits,
      // among the smallest possible (the tile's side) and the powers of two
      // above it (the sides GPUs like).
      std::vector<uint32_t> sides{std::max(h.dims.x, h.dims.y)};
      for (uint64_t p = 1; p < L.maxSide; p *= 2)
        if (p > sides[0]) sides.push_back(uint32_t(p));
      auto sideBytes = [&](uint64_t i) {
        return estimateFor(vox::AtlasLayout::make(h.dims, 0, sides[size_t(i)])).bytes();
      };
      suggestion = suggestSetting("--max-side", 0, sides.size() - 1, run.memoryLimit(), sideBytes,
                                  [&](uint64_t i) { return std::to_string(sides[size_t(i)]); });
    }
    run.checkMemory(estimate,
                    "building the atlases of " + o.scene + " (" + std::to_string(L.width) + " x " +
                        std::to_string(L.height) + " texels per layer, " + std::to_string(L.layers) +
                        (L.layers == 1 ? " layer)" : " layers)"),
                    suggestion);
  }

  // Layer by layer: fill every image of the layer in one pass over the
  // occupied voxels (empty texels stay 0), encode them, release them. So the
  // memory is one layer's images (at most --max-side squared texels each),
  // whatever the number of layers.
  auto progress = run.progress("atlas");
  const double total = double(std::max<uint64_t>(1, stats.occupied)) * L.layers;
  uint64_t done = 0;
  std::vector<std::exception_ptr> errors(outs.size() * (o.preview ? 2 : 1));
  struct Texel {
    uint64_t key;  // y << 32 | x
    std::array<uint64_t, 4> value;
  };
  for (uint32_t layer = 0; stream && layer < L.layers; ++layer) {
    run.phase(L.layers > 1 ? "fill layer " + std::to_string(layer) : "fill");
    std::vector<size_t> here;
    for (size_t i = 0; i < outs.size(); ++i)
      if (outs[i].info.layer == layer) here.push_back(i);
    auto isBitmap = [&](size_t i) {
      return outs[i].info.content == vox::AtlasContent::Occupancy ||
             outs[i].info.content == vox::AtlasContent::Occupancy2;
    };
    std::vector<std::vector<Texel>> texels(here.size());
    std::vector<uint64_t> occupiedKeys;
    scene.forEachVoxel([&](const vox::VoxelView& v) {
      if ((++done & 0xffff) == 0) progress->update(double(done) / total);
      const vox::TexelAddress t = L.toTexel(uint32_t(v.at.u), uint32_t(v.at.v), uint32_t(v.at.w));
      if (t.layer != layer) return;
      const uint64_t key = uint64_t(t.y) << 32 | t.x;
      if (wOcc || wOcc2) occupiedKeys.push_back(key);
      for (size_t j = 0; j < here.size(); ++j)
        if (!isBitmap(here[j]))
          texels[j].push_back({key, vox::atlasTexel(outs[here[j]].info.content, &v, idFormat, outs[here[j]].info.classId)});
    });
    std::sort(occupiedKeys.begin(), occupiedKeys.end());
    for (auto& list : texels) std::sort(list.begin(), list.end(), [](const Texel& a, const Texel& b) { return a.key < b.key; });

    run.phase(L.layers > 1 ? "write layer " + std::to_string(layer) : "write");
    vox::parallelForEach(here.size(), run.threads(), 1, [&](size_t j) {
      const size_t i = here[j];
      const Output& out = outs[i];
      const vox::Image& shape = out.image;
      std::vector<uint8_t> row(shape.rowBytes(), 0);
      size_t next = 0;
      bool dirty = false;
      const int bits = out.info.content == vox::AtlasContent::Occupancy ? 1 : 2;
      try {
        vox::writePngRows(shape.width, shape.height, shape.channels, shape.type, shape.text, out.tempPath,
                          o.compression, [&](uint32_t y) -> const uint8_t* {
                            if (dirty) std::fill(row.begin(), row.end(), uint8_t(0)), dirty = false;
                            if (isBitmap(i)) {
                              // OccupancyBitmap's packing: 8 (or 4) texels per byte along x.
                              for (; next < occupiedKeys.size() && (occupiedKeys[next] >> 32) == y; ++next, dirty = true) {
                                const uint32_t x = uint32_t(occupiedKeys[next]);
                                if (bits == 1) row[x >> 3] |= uint8_t(1u << (x & 7));
                                else row[x >> 2] |= uint8_t(1u << (2 * (x & 3)));
                              }
                            } else {
                              const std::vector<Texel>& list = texels[j];
                              for (; next < list.size() && (list[next].key >> 32) == y; ++next, dirty = true) {
                                const size_t px = uint32_t(list[next].key);
                                for (uint32_t c = 0; c < shape.channels; ++c) {
                                  const size_t k = px * shape.channels + c;
                                  if (shape.type == vox::SampleType::U8) row[k] = uint8_t(list[next].value[c]);
                                  else reinterpret_cast<uint16_t*>(row.data())[k] = uint16_t(list[next].value[c]);
                                }
                              }
                            }
                            return row.data();
                          });
      } catch (...) {
        errors[i] = std::current_exception();
      }
    });
    for (auto& e : errors)
      if (e) std::rethrow_exception(e);
  }
  for (uint32_t layer = 0; !stream && layer < L.layers; ++layer) {
    run.phase(L.layers > 1 ? "fill layer " + std::to_string(layer) : "fill");
    std::vector<size_t> here;  // outs of this layer, in file order
    for (size_t i = 0; i < outs.size(); ++i)
      if (outs[i].info.layer == layer) {
        vox::Image& img = outs[i].image;
        img.pixels.assign(img.rowBytes() * img.height, 0);
        here.push_back(i);
      }
    if (wOcc) bits1.emplace(oneLayer, 1);
    if (wOcc2) bits2.emplace(oneLayer, 2);
    // In parallel: the mapping is a bijection, so each voxel writes texels no
    // other voxel writes (bitmap bits, which share bytes, are OR-ed atomically);
    // the bytes do not depend on the split or the thread count.
    // Progress: a counter per piece on its own cache line (one shared atomic
    // counter, bounced between the cores on every voxel, cost more than the
    // texels), summed by whichever worker passes a multiple of 65536.
    constexpr size_t kPieces = 64;
    struct alignas(64) PieceCount {
      std::atomic<uint64_t> n{0};
    };
    std::vector<PieceCount> doneIn(kPieces);
    std::mutex progressMutex;
    auto doneHere = [&] {
      uint64_t sum = 0;
      for (const PieceCount& c : doneIn) sum += c.n.load(std::memory_order_relaxed);
      return sum;
    };
    vox::forEachVoxelInPieces(scene, run.threads(), kPieces, [&](const vox::VoxelView& v, size_t piece) {
      std::atomic<uint64_t>& count = doneIn[piece].n;  // written by this piece's worker only
      const uint64_t n = count.load(std::memory_order_relaxed) + 1;
      count.store(n, std::memory_order_relaxed);
      if ((n & 0xffff) == 0 && progressMutex.try_lock()) {
        progress->update(double(done + doneHere()) / total);
        progressMutex.unlock();
      }
      vox::TexelAddress t = L.toTexel(uint32_t(v.at.u), uint32_t(v.at.v), uint32_t(v.at.w));
      if (t.layer != layer) return;
      for (size_t i : here) {
        Output& out = outs[i];
        vox::Image& img = out.image;
        const size_t px = size_t(t.y) * img.width + t.x;
        switch (out.info.content) {
          case vox::AtlasContent::Occupancy:
          case vox::AtlasContent::Occupancy2: continue;  // bitmaps are packed below
          default: break;
        }
        const std::array<uint64_t, 4> val = vox::atlasTexel(out.info.content, &v, idFormat, out.info.classId);
        for (uint32_t c = 0; c < img.channels; ++c) {
          const size_t k = px * img.channels + c;
          switch (img.type) {
            case vox::SampleType::U8: img.pixels[k] = uint8_t(val[c]); break;
            case vox::SampleType::U16: reinterpret_cast<uint16_t*>(img.pixels.data())[k] = uint16_t(val[c]); break;
            case vox::SampleType::U32: reinterpret_cast<uint32_t*>(img.pixels.data())[k] = uint32_t(val[c]); break;
            case vox::SampleType::F16:
              reinterpret_cast<uint16_t*>(img.pixels.data())[k] = vox::floatToHalf(float(val[c]));
              break;
            case vox::SampleType::F32: reinterpret_cast<float*>(img.pixels.data())[k] = float(val[c]); break;
          }
        }
      }
      t.layer = 0;  // the bitmaps hold this layer only
      if (bits1) bits1->setOccupiedConcurrently(t);
      if (bits2) bits2->setOccupiedConcurrently(t);
    });
    done += doneHere();
    for (size_t i : here) {
      if (outs[i].info.content == vox::AtlasContent::Occupancy) outs[i].image.pixels = std::move(bits1->layerBytes(0));
      if (outs[i].info.content == vox::AtlasContent::Occupancy2) outs[i].image.pixels = std::move(bits2->layerBytes(0));
    }
    bits1.reset(), bits2.reset();

    // Encode: files in parallel, and each file in parallel too: PNGs (atlases
    // and the packed 1- and 2-bit bitmaps alike) are deflated in row slices
    // (formats/image/image_png_parallel.cpp), EXRs in scanline blocks on
    // OpenEXR's workers, so one large file (the usual case: a summary atlas)
    // keeps every core busy; bytes depend on neither. --preview adds one job
    // per file after the data files: a preview is drawn from its data image
    // (so it shows exactly what was written). The first failing file, in file
    // order, is reported.
    run.phase(L.layers > 1 ? "write layer " + std::to_string(layer) : "write");
    const size_t jobs = here.size() * (o.preview ? 2 : 1);
    vox::parallelForEach(jobs, run.threads(), 1, [&](size_t j) {
      const bool isPreview = j >= here.size();
      const size_t i = here[isPreview ? j - here.size() : j];
      try {
        if (isPreview) {
          const Output& out = outs[i];
          const vox::AtlasPreview preview =
              vox::atlasPreview(out.image, out.info, h.classes, fs::path(out.path).filename().string());
          vox::writeAtlasPreview(preview, out.previewTempPath, run.threads());
        } else if (outs[i].exr) {
          vox::writeExr(outs[i].image, outs[i].tempPath, vox::ExrCompression::Zip, run.threads());
        } else {
          vox::writePngParallel(outs[i].image, outs[i].tempPath, o.compression, run.threads());
        }
      } catch (...) {
        errors[isPreview ? outs.size() + i : i] = std::current_exception();
      }
    });
    for (size_t i : here) std::vector<uint8_t>().swap(outs[i].image.pixels);
    for (auto& e : errors)
      if (e) std::rethrow_exception(e);
  }
  progress->done();

  // Sidecar: the layout and every file, for engines that do not read PNG text chunks.
  std::vector<vox::AtlasSidecarEntry> sideFiles;
  for (const Output& out : outs) sideFiles.push_back({out.info, fs::path(out.path).filename().string()});
  const std::string sidePath = (fs::path(o.outDir) / (stem + ".atlas.json")).string();
  vox::writeFileBytes(run.output(sidePath), vox::atlasSidecarJson(o.scene, L, sideFiles));

  const size_t files = outs.size() * (o.preview ? 2 : 1) + 1;
  run.counts() = {{"occupied_voxels", stats.occupied}, {"files", files}, {"layers", L.layers},
                  {"atlas", {L.width, L.height}}, {"previews", o.preview ? outs.size() : 0}};
  run.noteWhenDone("wrote " + counted(files, "file", "files") + " to " + o.outDir + " (" + std::to_string(L.width) + " x " +
           std::to_string(L.height) + (L.layers > 1 ? " x " + std::to_string(L.layers) + " layers" : "") + ")");
  const int code = run.finish();  // a failed commit leaves no file: the directory goes too
  outDir.keep();
  return code;
}

const EnumNames<vox::TexelFormat>& texelFormatNames() {
  static const EnumNames<vox::TexelFormat> names = [] {
    EnumNames<vox::TexelFormat> n;
    for (vox::TexelFormat f : vox::kTexelFormats) n.emplace_back(vox::texelFormatName(f), f);
    return n;
  }();
  return names;
}

}  // namespace

Command registerBuildAtlas(CLI::App& root) {
  auto o = std::make_shared<BuildAtlasOptions>();
  CLI::App* cmd = root.add_subcommand("build-atlas", "Write a scene's atlases and occupancy bitmaps (PNG/EXR)");
  cmd->footer(
      "Without content flags: --summary and --occupancy. Files are DIR/STEM.CONTENT[.CLASS][.layerN].png|exr\n"
      "plus DIR/STEM.atlas.json; every image also carries its layout in a \"vox:atlas\" text entry.\n"
      "--preview adds DIR/NAME.preview.png beside each file (not listed in the .atlas.json).");
  cmd->add_option("scene", o->scene, "Scene (.vdb)")->required();
  cmd->add_option("-o,--output", o->outDir, "Output directory (created if missing)")->required();
  cmd->add_option("--stem", o->stem, "File name stem (default: the scene's)");
  cmd->add_flag("--summary", o->summary, "Summary atlas RGBA8 (cls, conf, obs, mrg)");
  cmd->add_flag("--occupancy", o->occupancy, "1-bit occupancy bitmap (8 voxels per byte along x)");
  cmd->add_flag("--occupancy2", o->occupancy2, "2-bit occupied + touched bitmap (touched bits 0)");
  cmd->add_flag("--identity", o->identity, "Identity atlas RGB = (u, v, w) (computable; off by default)");
  cmd->add_flag("--color", o->color, "Colour atlas RGBA8 sRGB (scenes with colour)");
  cmd->add_flag("--votes", o->votes, "One vote layer per class present (narrowest exact: R8, R16 PNG or R32UI EXR)");
  cmd->add_flag("--all", o->all, "Every content that applies to the scene");
  cmd->add_flag("--preview", o->preview,
                "Also a viewable NAME.preview.png beside each file: class colours, ramps, black/white bitmaps "
                "(formats/image/ATLAS.md \"Previews\")");
  o->identityFormatOption =
      addEnumOption(*cmd, "--format", o->identityFormat, texelFormatNames(), "Identity atlas format (default: narrowest exact)")
          ->default_str("");
  cmd->add_option("--tiles-per-row", o->tilesPerRow, "Tiles per atlas row (default: smallest, squarest)");
  cmd->add_option("--max-side", o->maxSide, "Largest texture side; further tile rows go to layers")->capture_default_str();
  cmd->add_option("--compression", o->compression, "PNG zlib level 0-9")->check(CLI::Range(0, 9))->capture_default_str();
  addCommonOptions(*cmd, o->common);
  return {cmd, [o] { return runBuildAtlas(*o); }};
}

}  // namespace voxcli
