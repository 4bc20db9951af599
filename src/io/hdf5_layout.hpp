#pragma once
// A chunked HDF5 dataset's data layout message stores the chunk's dimensions followed by one more, the
// size in bytes of one value (HDF5 File Format Specification 3.0, IV.A.2.i "The Data Layout Message").
// libhdf5 1.10.8 does not compare that size with the datatype's and its API does not show it
// (H5Pget_chunk returns the other dimensions): a corrupt one makes H5Dread copy a later part of a
// decompressed chunk from past its buffer (a heap over-read, silent without a sanitizer; found
// 2026-11-27 by the dsec_events fuzz harness). This reads the layout message from the dataset's object
// header in the file's own bytes so the readers can compare the two before they read a value.

#include <hdf5.h>

#include <cstdint>
#include <string>

namespace asynevo::io_detail {

/// The value size, in bytes, that the data layout message of the open chunked dataset `dataset` of the
/// file at `path` declares; 0 when the dataset is not chunked (contiguous, compact or virtual storage).
/// Throws InputError naming `path`, the dataset `name` and the byte offset when the object header or its
/// layout message cannot be read (truncated, corrupt, or a message version HDF5 1.10 does not write).
uint64_t h5ChunkValueSize(const std::string& path, hid_t dataset, const std::string& name);

/// Throws InputError naming `path` and `name` when the chunked dataset's layout declares values of
/// another size than `type_size`, the size of its datatype.
void h5CheckChunkValueSize(const std::string& path, hid_t dataset, const std::string& name,
                           std::size_t type_size);

}  // namespace asynevo::io_detail
