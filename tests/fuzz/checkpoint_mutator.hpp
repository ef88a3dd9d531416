// A mutator that knows the layout of checkpoint files (engine/io/checkpoint.cpp): it changes the
// header's counts, the values of a field and the lengths of its arrays, and whole field records,
// then mostly recomputes the FNV-1a checksum, so that the reader's checks of lengths, indices and
// values are reached, not only its checksum test.
#pragma once

#include <cstddef>
#include <cstdint>

namespace silt::fuzz {

// libFuzzer's custom mutator contract: mutate data[0, size) in place within max_size bytes and
// return the new size; `seed` decides everything (the same seed gives the same mutation).
size_t mutate_checkpoint(uint8_t* data, size_t size, size_t max_size, unsigned int seed);

// Writes the checksum of data[0, size - 8) into its last 8 bytes (nothing when too short).
void fix_checksum(uint8_t* data, size_t size);

}  // namespace silt::fuzz
