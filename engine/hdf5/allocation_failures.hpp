#pragma once
// What a failed memory allocation while reading a file means.
//
// A damaged file can claim any size where HDF5 allocates before it can check:
// a variable-length string whose stored length is damaged makes H5Aread /
// H5Dread allocate that length (up to 4 GB per string, in H5T__conv_vlen) before
// the read finds the damage. No check ahead of the read sees that length, so a
// reader of a file it does not trust bounds its address space instead
// (engine/run/reading_memory_cap.hpp) and then knows what a failed allocation
// means:
//   - kDamage: the address space is bounded by ggk at far more than a whole read
//     of the file needs, so an allocation that fails asks for more than the file
//     can hold: the object read is damaged, an error naming it (as any damage);
//   - kOutOfMemory (the default): the machine or the user's limit (ulimit -v) ran
//     out: std::bad_alloc, which the commands report as "not enough memory",
//     never as damage.
// Under kOutOfMemory and a finite RLIMIT_AS, zlib's "inflate() failed" also
// counts as a failed allocation: the read checks each chunk's Fletcher32 sum
// before it inflates it, so a chunk that fails to inflate after its sum passed
// failed for memory (zlib's Z_MEM_ERROR, which HDF5 does not tell apart).
//
// Process-wide; set only while one thread reads (a reading child, or `run`
// before its computing threads start).

namespace ggk::engine {

enum class AllocationFailure { kOutOfMemory, kDamage };

void set_allocation_failures(AllocationFailure meaning);
AllocationFailure allocation_failures();

}  // namespace ggk::engine
