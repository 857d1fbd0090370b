#include "formats/export/ply_writer.h"

#include <bit>
#include <cstring>
#include <vector>

#include "formats/export/output_file.h"

namespace vox {

static_assert(std::endian::native == std::endian::little, "the PLY body is written little-endian");

PlyWriteResult writeVoxelPly(const ClassVolume& volume, const ClassTable& classes, FaceColor color,
                             const GridFrame& frame, const std::string& path) {
  VoxelColors colors(classes, color);
  OutputFile out(path);
  out.write("ply\nformat binary_little_endian 1.0\n"
            "comment voxbake vox export: occupied voxel centres (world units), colour (sRGB), class id\n"
            "element vertex " +
            std::to_string(volume.occupiedCount()) +
            "\nproperty float x\nproperty float y\nproperty float z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar class\nend_header\n");
  constexpr size_t kRecord = 16;  // 3 floats, 3 colour bytes, the class byte
  std::vector<uint8_t> block;
  block.reserve(ClassVolume::kBrickVoxels * kRecord);
  PlyWriteResult r;
  for (const ClassVolume::Brick& b : volume.bricks()) {
    block.clear();
    for (int i = 0; i < ClassVolume::kBrickVoxels; ++i) {
      const uint8_t cls = b.classes[size_t(i)];
      if (!cls) continue;
      const Coord3 c = b.at(i);
      const float xyz[3] = {float((c.u + 0.5) * frame.voxelSize + frame.origin[0]),
                            float((c.v + 0.5) * frame.voxelSize + frame.origin[1]),
                            float((c.w + 0.5) * frame.voxelSize + frame.origin[2])};
      const Rgb8 rgb = colors(b, i);
      uint8_t record[kRecord];
      std::memcpy(record, xyz, 12);
      record[12] = rgb.r, record[13] = rgb.g, record[14] = rgb.b, record[15] = cls;
      block.insert(block.end(), record, record + kRecord);
      ++r.points;
    }
    out.write(block.data(), block.size());
  }
  out.close();
  r.bytes = out.written();
  r.uncolored = colors.uncolored();
  return r;
}

}  // namespace vox
