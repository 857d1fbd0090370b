// A bounds-checked walk over an OpenVDB (.vdb) file before OpenVDB reads it.
//
// Why our own: OpenVDB's reader trusts every count and size in the file. A
// truncated file makes it allocate a garbage string length (a 100-byte prefix of
// a scene made it allocate 14 GB); a compressed block whose stored size is
// negative makes io::bloscFromStream copy that many bytes into a leaf buffer of
// 512 values (a heap overflow); a Blosc header whose compressed size exceeds the
// block makes Blosc read past OpenVDB's buffer. So every byte OpenVDB will read
// is walked here first, in the order OpenVDB reads it (openvdb/io/Archive.cc,
// tree/RootNode.h, InternalNode.h, LeafNode*.h, io/Compression.h of OpenVDB
// 10, file format 222-224), and a file is refused with the element that is
// wrong unless every read OpenVDB will do stays inside the file and inside the
// buffer it reads into:
//
//   header      magic, file version (222..224), library version, grid offsets,
//               UUID
//   metadata    (file and per grid) every entry's name, type and size; sizes of
//               known types must match the type; bool values must be 0 or 1;
//               OpenVDB's delayed-load metadata is parsed with its Blosc blocks
//   descriptors name, type, instance parent, and the grid's [start, end) range
//               inside the file, grids back to back
//   per grid    compression flags, metadata, transform (known map types), and
//               for grids of a known value type (bool, mask, float, double,
//               int32, int64, vec3i, vec3s, vec3d; half-float storage included)
//               the whole tree: root background, tiles and children (aligned,
//               sorted, no duplicates), internal nodes (child and value masks,
//               their compressed values) and leaves (value masks, origins,
//               compressed values); the topology must end at the grid's block
//               offset and the leaf buffers at its end offset.
//   blocks      every compressed block's stored size against the bytes left and
//               against the byte count the masks imply; Blosc headers against
//               the block; and (Full) the block is decompressed into a buffer of
//               the expected size, which must come out exactly full.
//
// Grids of other types (OpenVDB point grids) get their framing checked only and
// are marked unchecked: CheckedVdbFile (vdb_checked_file.h) refuses to hand
// them to OpenVDB. Coordinates of root tiles and children must lie within
// +-2^30 voxels, so that node bounds never overflow 32-bit arithmetic.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace vox {

struct VdbGridFrame {
  std::string uniqueName, type;  // type as stored, e.g. "Tree_float_5_4_3_HalfFloat"
  std::string instanceParent;    // empty unless the grid shares another grid's tree
  int64_t gridPos = 0, blockPos = 0, endPos = 0;
  bool checked = false;       // the payload was walked (Full): OpenVDB may read it
  std::string uncheckedWhy;   // why not, when !checked
  uint64_t leafCount = 0;     // leaves walked (Full)
  uint64_t activeLeafVoxels = 0;  // active voxels of those leaves (their value masks' set bits; tiles not counted)
  uint64_t upperNodes = 0, lowerNodes = 0;  // internal nodes walked (Full): 32^3 and 16^3 children
};

struct VdbFrame {
  uint32_t fileVersion = 0;
  uint32_t libraryMajor = 0, libraryMinor = 0;
  std::vector<std::string> metadataNames;
  std::vector<VdbGridFrame> grids;
};

/// How far the walk goes. Framing: header, file metadata and grid descriptors
/// with their byte ranges (enough to tell a file cut short by a full disk).
/// Full: also every grid's payload, every compressed block decompressed.
enum class VdbCheck { Framing, Full };

/// Walks `path`. Throws vox::Error (BadInput) naming the file, the grid and the
/// element (header field, metadata entry, node, mask, compressed block) that is
/// truncated, out of range or inconsistent. A Full walk of a file whose status
/// last changed over two seconds earlier is remembered for the process (keyed
/// by path, device, inode, size, modification and change times), so a command
/// that opens a file twice walks it once.
VdbFrame checkVdbStructure(const std::string& path, VdbCheck depth = VdbCheck::Full);

/// Same on bytes in memory.
VdbFrame checkVdbStructure(const uint8_t* data, size_t size, const std::string& nameForMessages,
                           VdbCheck depth = VdbCheck::Full);

/// True when the file starts with OpenVDB's magic number (cheap sniffing).
bool looksLikeVdb(const std::string& path);

/// The checks CheckedVdbFile (vdb_checked_file.h) and the scene readers make before walking `path`: it exists, is not a
/// directory, is a regular file (not a FIFO, socket or device), can be
/// opened and starts with OpenVDB's magic number. Throws vox::Error (BadInput).
void checkVdbFileOpenable(const std::string& path);

// ---------------------------------------------------------------- reading through the walk
// A reader that builds its trees from the walk's own decoding instead of
// handing the file to OpenVDB afterwards (the one-pass scene reader,
// vdb_scene_direct_read.h): every byte it is given has been checked exactly
// as checkVdbStructure checks it, and every compressed block is decompressed
// once.

/// What the walk knows of a grid once its topology is walked. Pointers point
/// into the walked bytes.
struct VdbGridLayout {
  uint32_t compression = 0;                    // io::COMPRESS_* flags of the grid
  bool halfFloat = false;                      // values are stored as half floats
  const uint8_t* metadata = nullptr;           // the grid metadata as stored (count, entries)
  size_t metadataBytes = 0;
  const uint8_t* transform = nullptr;          // the transform as stored (map type, values)
  size_t transformBytes = 0;
  const uint8_t* background = nullptr;         // the root's background value
  uint32_t valueSize = 0;                      // bytes of one value in memory (bool: 1)
  /// No root tiles, every internal node has children and no tiles, and
  /// every inactive value of the internal nodes is the background: the tree
  /// is its leaves (adding them to an empty tree gives the tree OpenVDB reads).
  bool leavesOnly = false;
};

/// One leaf's buffer as io::readCompressedValues / LeafNode<bool>::readBuffers
/// take it; pointers are valid during the call only.
struct VdbLeafValues {
  std::array<int32_t, 3> origin{};
  const uint8_t* valueMask = nullptr;  // 64 bytes: the active voxels
  const uint8_t* boolValues = nullptr;  // bool grids: 64 bytes of value bits; else nullptr
  // Other grids: the compression metadata byte (io/Compression.h), the
  // inactive values it stores (nullptr when it stores none), the selection
  // mask (nullptr when none), and `count` decoded values of the grid's value
  // size: all 512, or the active ones in voxel order.
  int8_t compressionMeta = 0;
  const uint8_t* inactive[2] = {nullptr, nullptr};
  const uint8_t* selectionMask = nullptr;
  const uint8_t* values = nullptr;
  size_t count = 0;
};

/// What the walk does with a grid's leaf buffers.
enum class VdbLeafUse {
  Deliver,  // decompress and check every block and hand each leaf to VdbWalkSink::leaf
  Frame,    // check the framing and Blosc headers only, decompress nothing (the grid is not read)
};

/// Receives a walk (walkVdbInto). Calls come from the walking thread except
/// leaf(), which runs concurrently for distinct leaves. An exception thrown by
/// a call ends the walk and reaches walkVdbInto's caller (from leaf(): the one
/// of the first leaf in file order that threw).
class VdbWalkSink {
 public:
  virtual ~VdbWalkSink() = default;
  /// The file metadata as stored (count, entries), after the header.
  virtual void fileMetadata(const uint8_t* bytes, size_t size) = 0;
  /// Once every grid's framing and topology are walked (frame.grids have
  /// their leaf counts; `grids` is parallel to them; instances and grids of
  /// types the walk cannot check have default layouts), before any leaf
  /// buffer: what to do with each grid's leaves.
  virtual std::vector<VdbLeafUse> topologyWalked(const VdbFrame& frame, const std::vector<VdbGridLayout>& grids) = 0;
  /// Leaf `index` (file order) of grid `grid`, for grids given Deliver.
  virtual void leaf(size_t grid, size_t index, const VdbLeafValues& values) = 0;
  /// Every leaf of a Deliver grid has been handed over and its bytes checked.
  virtual void gridDone(size_t grid) = 0;
};

/// A Full walk of `data` that hands the grids to `sink`. The checks and
/// messages are checkVdbStructure's; the order differs in one way: the
/// topology of every grid is walked before the first leaf buffer, so of two
/// faults in one file the one in a later grid's topology may be named first.
/// Leaf blocks are decompressed in parallel (libvox/core/parallel.h); what
/// is delivered and which fault is named do not depend on the thread count.
VdbFrame walkVdbInto(const uint8_t* data, size_t size, const std::string& nameForMessages, VdbWalkSink& sink);

class FileView;
struct VdbWalkState;

/// walkVdbInto over a file, in two steps: the constructor maps the file and
/// walks its framing and every grid's topology (the frame then has its leaf
/// counts), finish() hands the grids to a sink and walks the leaf buffers.
/// For a command that estimates several files' memory from their topology
/// before it reads any (vox merge): each file is read once. Between the two,
/// the file stays mapped (the pages the topology walk touched are resident)
/// and the leaves' origins are kept (24 bytes a leaf).
class VdbTopologyWalk {
 public:
  /// checkVdbFileOpenable, then the walk's first pass. Throws its vox::Error
  /// (BadInput) naming the file.
  explicit VdbTopologyWalk(const std::string& path);
  ~VdbTopologyWalk();
  VdbTopologyWalk(const VdbTopologyWalk&) = delete;
  VdbTopologyWalk& operator=(const VdbTopologyWalk&) = delete;
  const std::string& path() const { return path_; }
  const VdbFrame& frame() const { return frame_; }
  /// The rest of walkVdbInto (the sink gets every call it would), once;
  /// then releases the mapping and the leaves' origins.
  VdbFrame finish(VdbWalkSink& sink);

 private:
  std::string path_;
  VdbFrame frame_;
  std::unique_ptr<FileView> file_;
  std::unique_ptr<VdbWalkState> state_;
};

}  // namespace vox
