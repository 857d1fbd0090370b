// CRC32C (Castagnoli, polynomial 0x1EDC6F41, reflected 0x82F63B78, initial and
// final XOR 0xFFFFFFFF), as in iSCSI (RFC 3720), ext4 and SSE4.2's crc32
// instruction. crc32c("123456789") = 0xE3069283.
//
// Uses the SSE4.2 instruction when the CPU has it (checked once at run time),
// otherwise a portable slicing-by-8 table; both give the same values.
#pragma once

#include <cstddef>
#include <cstdint>

namespace vox {

/// CRC32C of `size` bytes. To checksum in pieces, pass the previous result as
/// `crc` (start with 0): crc32c(b, nb, crc32c(a, na)) == crc32c(a+b).
uint32_t crc32c(const void* data, size_t size, uint32_t crc = 0);

/// The portable table implementation (for tests and CPUs without SSE4.2).
uint32_t crc32cPortable(const void* data, size_t size, uint32_t crc = 0);

/// True when crc32c uses the SSE4.2 instruction on this machine.
bool crc32cHardware();

}  // namespace vox
