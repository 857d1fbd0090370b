// Google Benchmark over the image readers, one core: a 1024^2 RGBA8 label
// image of flat regions (what render-canonical's class and normal modes
// write) as PNG, and a 1024^2 float depth image as ZIP-compressed EXR, both
// written by vox's writers, read by vox (readPng, readExr: libdeflate, raw EXR
// chunks) and by the libraries' own paths (libpng with zlib, OpenEXR's
// readPixels) in the same run; and a 2048^2 photographic RGB texture as PNG
// (libpng's default adaptive filters, mostly PAETH) decoded by vox's texture
// decoder and by stb_image. Reports decoded bytes per second.
// docs/bench-fuse.md "Reading views" and docs/gltf.md "PNG textures" have the
// figures and why.
#include <ImfFrameBuffer.h>
#include <ImfInputFile.h>
#include <benchmark/benchmark.h>
#include <png.h>
#include <stb/stb_image.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "formats/image/image.h"
#include "formats/mesh/texture_image.h"

namespace {

constexpr uint32_t kSize = 1024;

std::string scratch(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("vox-bench-image-read-" + name)).string();
}

// Flat regions with straight and curved edges: a few hundred distinct colours.
const std::string& labelPng() {
  static const std::string path = [] {
    vox::Image img(kSize, kSize, 4, vox::SampleType::U8);
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x) {
        uint8_t* p = img.pixels.data() + (size_t(y) * kSize + x) * 4;
        const double dx = double(x) - 512, dy = double(y) - 600;
        const bool sky = y < 300 && dx * dx + dy * dy > 350.0 * 350.0;
        const uint32_t region = (x / 96) * 7 + (y / 80) * 3 + (dx * dx + dy * dy < 200.0 * 200.0 ? 50 : 0);
        p[0] = uint8_t(region * 37), p[1] = uint8_t(region * 91), p[2] = uint8_t(region * 53), p[3] = sky ? 0 : 255;
      }
    const std::string out = scratch("label.png");
    vox::writePng(img, out);
    return out;
  }();
  return path;
}

// Smooth depth over most pixels, 0 (no depth) in the sky.
const std::string& depthExr() {
  static const std::string path = [] {
    vox::Image img(kSize, kSize, 1, vox::SampleType::F32);
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x) {
        const float d = y < 300 ? 0.0f : float(400.0 + 80.0 * std::sin(x * 0.01) + 0.37 * y + 3.0 * std::cos(x * y * 1e-4));
        std::memcpy(img.pixels.data() + (size_t(y) * kSize + x) * 4, &d, 4);
      }
    const std::string out = scratch("depth.exr");
    vox::writeExr(img, out, vox::ExrCompression::Zip, 1);
    return out;
  }();
  return path;
}

void VoxPng(benchmark::State& state) {
  const std::string& path = labelPng();
  for (auto _ : state) benchmark::DoNotOptimize(vox::readPng(path).pixels.data());
  state.SetBytesProcessed(int64_t(state.iterations()) * kSize * kSize * 4);
}

void LibpngPng(benchmark::State& state) {
  const std::string& path = labelPng();
  std::vector<uint8_t> px(size_t(kSize) * kSize * 4);
  std::vector<png_bytep> rows(kSize);
  for (uint32_t y = 0; y < kSize; ++y) rows[y] = px.data() + size_t(y) * kSize * 4;
  for (auto _ : state) {
    FILE* f = std::fopen(path.c_str(), "rb");
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
      state.SkipWithError("libpng failed");
      break;
    }
    png_init_io(png, f);
    png_read_info(png, info);
    png_read_image(png, rows.data());
    png_read_end(png, info);
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(f);
    benchmark::DoNotOptimize(px.data());
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * kSize * kSize * 4);
}

void VoxExr(benchmark::State& state) {
  const std::string& path = depthExr();
  for (auto _ : state) benchmark::DoNotOptimize(vox::readExr(path).pixels.data());
  state.SetBytesProcessed(int64_t(state.iterations()) * kSize * kSize * 4);
}

void OpenExrReadPixels(benchmark::State& state) {
  const std::string& path = depthExr();
  std::vector<float> px(size_t(kSize) * kSize);
  for (auto _ : state) {
    Imf::InputFile in(path.c_str());
    Imf::FrameBuffer fb;
    fb.insert("R", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(px.data()), 4, 4 * kSize));
    in.setFrameBuffer(fb);
    in.readPixels(0, int(kSize) - 1);
    benchmark::DoNotOptimize(px.data());
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * kSize * kSize * 4);
}

// Smooth shading with a little noise, written by libpng with its default
// (adaptive) filters, as image editors and exporters write textures.
const std::string& photoTexture() {
  static const std::string bytes = [] {
    constexpr uint32_t kTex = 2048;
    std::vector<uint8_t> px(size_t(kTex) * kTex * 3);
    uint32_t seed = 1;
    for (uint32_t y = 0; y < kTex; ++y)
      for (uint32_t x = 0; x < kTex; ++x) {
        seed = seed * 1664525u + 1013904223u;
        uint8_t* p = px.data() + (size_t(y) * kTex + x) * 3;
        const double v = 128 + 60 * std::sin(x * 0.013 + std::cos(y * 0.007) * 3) + 30 * std::sin(y * 0.031);
        p[0] = uint8_t(v + (seed >> 29)), p[1] = uint8_t(v * 0.8 + ((seed >> 26) & 7)), p[2] = uint8_t(v * 0.6 + ((seed >> 23) & 7));
      }
    const std::string path = scratch("texture.png");
    FILE* f = std::fopen(path.c_str(), "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, kTex, kTex, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (uint32_t y = 0; y < kTex; ++y) png_write_row(png, px.data() + size_t(y) * kTex * 3);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    std::FILE* r = std::fopen(path.c_str(), "rb");
    std::string out;
    char buf[1 << 16];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, r)) > 0;) out.append(buf, n);
    std::fclose(r);
    return out;
  }();
  return bytes;
}

void VoxPngTexture(benchmark::State& state) {
  const std::string& bytes = photoTexture();
  for (auto _ : state) {
    vox::TextureImage image;
    std::string why;
    if (!vox::decodeTextureImage(bytes, image, why)) state.SkipWithError(why.c_str());
    benchmark::DoNotOptimize(image.rgba.data());
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * 2048 * 2048 * 4);
}

void StbImagePngTexture(benchmark::State& state) {
  const std::string& bytes = photoTexture();
  for (auto _ : state) {
    int w = 0, h = 0, n = 0;
    stbi_uc* px = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &w, &h, &n, 4);
    benchmark::DoNotOptimize(px);
    stbi_image_free(px);
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * 2048 * 2048 * 4);
}

BENCHMARK(VoxPng)->Unit(benchmark::kMillisecond);
BENCHMARK(VoxPngTexture)->Unit(benchmark::kMillisecond);
BENCHMARK(StbImagePngTexture)->Unit(benchmark::kMillisecond);
BENCHMARK(LibpngPng)->Unit(benchmark::kMillisecond);
BENCHMARK(VoxExr)->Unit(benchmark::kMillisecond);
BENCHMARK(OpenExrReadPixels)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
