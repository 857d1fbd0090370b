// Texture images decoded while the mesh is baked instead of before: decoding
// a photo-like 2048^2 JPEG costs about 28 ms of one core (libjpeg-turbo's
// entropy decoding, whatever its options), so the five of the benchmark's
// model (docs/gltf.md) cost as much as its whole --res 256 bake without
// them. A mesh read with a DeferredTextures (readMeshFile's last
// argument) comes back at once with its textures named, sampled and wrapped
// as the file says but without pixels (width = height = 0), their images
// decoding on TBB's threads meanwhile, within the process's thread limit
// (tools/cli caps TBB at --threads; at --threads 1 nothing runs before
// take(mesh, true), which then decodes on the calling thread). The voxelizer takes
// the pixels when it needs them (VoxelizeSettings::awaitTextures calls
// take()), after the surface pass's geometry: those decoded by then first,
// while the others finish.
//
// The result does not depend on it: the same pixels, and an image that does
// not decode is the same error (message, exit 3) as when it is decoded while
// the file is read, from take(mesh, true). Only glTF colour textures are deferred
// (OBJ map_Kd files are decoded while read), and never with
// ignoreMissingMaterials, whose warning for an undecodable image must be
// known when the read returns.
//
// Thread-safety: one owner; take(), finish() and the other members are called
// from one thread, with nothing reading the mesh's textures meanwhile. The
// decoding tasks touch only their own job's bytes and result.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "libvox/mesh/mesh.h"

namespace vox {

class DeferredTextures {
 public:
  DeferredTextures();
  /// Waits for decodes still running (a bake that failed elsewhere); their pixels are dropped.
  ~DeferredTextures();
  DeferredTextures(const DeferredTextures&) = delete;
  DeferredTextures& operator=(const DeferredTextures&) = delete;

  /// Images still to be put into the mesh (0 once take(mesh, true) returned).
  size_t pendingImages() const;

  /// The pixel bytes the pending textures will hold (width x height x 4 per
  /// texture, read from the images' headers), for the bake's memory estimate.
  uint64_t pendingPixelBytes() const;

  /// Moves the pixels of every image decoded by now into the textures of
  /// `mesh` that use it (copies for all but the last; a texture's width is 0
  /// until then), and returns whether every image is in. With `wait`, waits
  /// for every decode first (decoding the images not begun on this thread)
  /// and throws vox::Error (BadInput, Setting::IgnoreMissingMaterials) naming
  /// the first image, in index order, that does not decode: the error a read
  /// that decodes first throws. Once everything is in, calls do nothing.
  bool take(Mesh& mesh, bool wait);
  /// take(mesh, true).
  void finish(Mesh& mesh);

  /// The images decoded in the background, the seconds their decoding took
  /// (elapsed on the thread that decoded each, summed over images), and the
  /// seconds take(mesh, true) waited for them; complete after it.
  size_t decodedImages() const;
  double decodeSeconds() const;
  double waitSeconds() const;

  // For the readers (formats/mesh/gltf_images.cpp): one job per image.
  struct Job;
  /// Adds an image to decode: its encoded bytes, and `name` for the error
  /// message ("model.glb: image 3 'wood.jpg'"). Returns its job index.
  size_t addImage(std::string bytes, std::string name);
  /// Texture `meshTexture` of the mesh being read uses job `job`'s pixels.
  void addTexture(size_t job, size_t meshTexture);
  /// Starts decoding every job added (once; no job may be added afterwards).
  void start();

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace vox
