#include "formats/mesh/deferred_textures.h"

#include <tbb/task_group.h>

#include <atomic>
#include <chrono>

#include "formats/mesh/texture_image.h"

namespace vox {

struct DeferredTextures::Job {
  std::string bytes, name;
  std::vector<size_t> textures;  // the mesh's textures that take its pixels
  uint64_t pixelBytes = 0;       // from the header, per texture
  bool taken = false;            // its pixels are in the mesh
  // Written by the decoding task only, before it sets `done`:
  struct {
    TextureImage image;
    std::string why;
    bool ok = false;
  } result;
  double seconds = 0;
  std::atomic<bool> done{false};
};

struct DeferredTextures::State {
  std::vector<std::unique_ptr<Job>> jobs;
  tbb::task_group group;
  bool started = false, finished = false;
  double waited = 0;
};

DeferredTextures::DeferredTextures() : s_(std::make_unique<State>()) {}

DeferredTextures::~DeferredTextures() {
  if (s_->started && !s_->finished) {
    s_->group.cancel();  // tasks not begun are dropped
    s_->group.wait();
  }
}

size_t DeferredTextures::addImage(std::string bytes, std::string name) {
  auto job = std::make_unique<Job>();
  uint32_t w = 0, h = 0;
  if (textureImageSize(job->bytes = std::move(bytes), w, h)) job->pixelBytes = uint64_t(w) * h * 4;
  job->name = std::move(name);
  s_->jobs.push_back(std::move(job));
  return s_->jobs.size() - 1;
}

void DeferredTextures::addTexture(size_t job, size_t meshTexture) { s_->jobs[job]->textures.push_back(meshTexture); }

void DeferredTextures::start() {
  if (s_->started) return;
  s_->started = true;
  // One task per image, as decodeImages: a large texture on one thread, several in parallel.
  for (const std::unique_ptr<Job>& j : s_->jobs)
    s_->group.run([job = j.get()] {
      const auto t0 = std::chrono::steady_clock::now();
      job->result.ok = decodeTextureImage(job->bytes, job->result.image, job->result.why);
      job->bytes = std::string();
      job->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      job->done.store(true, std::memory_order_release);
    });
}

size_t DeferredTextures::pendingImages() const {
  size_t n = 0;
  for (const std::unique_ptr<Job>& job : s_->jobs) n += !job->taken;
  return n;
}

uint64_t DeferredTextures::pendingPixelBytes() const {
  uint64_t bytes = 0;
  for (const std::unique_ptr<Job>& job : s_->jobs)
    if (!job->taken) bytes += job->pixelBytes * job->textures.size();
  return bytes;
}

bool DeferredTextures::take(Mesh& mesh, bool wait) {
  if (s_->finished) return true;
  start();
  if (wait) {
    const auto t0 = std::chrono::steady_clock::now();
    s_->group.wait();
    s_->waited += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    s_->finished = true;
    // The first image in index order that does not decode, as decodeImages says it.
    for (const std::unique_ptr<Job>& job : s_->jobs)
      if (!job->result.ok) throwUndecodableImage(job->name, job->result.why);
  }
  bool all = true;
  for (const std::unique_ptr<Job>& job : s_->jobs) {
    if (job->taken) continue;
    if (!job->done.load(std::memory_order_acquire) || !job->result.ok) {  // a failure waits for its turn above
      all = false;
      continue;
    }
    for (size_t k = 0; k < job->textures.size(); ++k) {
      MeshTexture& t = mesh.textures[job->textures[k]];
      t.width = job->result.image.width;
      t.height = job->result.image.height;
      if (k + 1 == job->textures.size()) t.rgba = std::move(job->result.image.rgba);
      else t.rgba = job->result.image.rgba;
    }
    job->taken = true;
  }
  return all;
}

void DeferredTextures::finish(Mesh& mesh) { take(mesh, true); }

size_t DeferredTextures::decodedImages() const { return s_->jobs.size(); }

double DeferredTextures::decodeSeconds() const {
  double sum = 0;
  if (s_->finished)
    for (const std::unique_ptr<Job>& job : s_->jobs) sum += job->seconds;
  return sum;
}

double DeferredTextures::waitSeconds() const { return s_->waited; }

}  // namespace vox
