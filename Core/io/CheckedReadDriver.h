#pragma once
// A read-only HDF5 file driver (a POSIX file read with pread) that checks every global heap
// collection before HDF5 decodes it.
//
// Why: variable-length strings (the state file's `format` and `model` attributes, and h5py's
// strings) live in the file's global heap. HDF5 1.10.8 decodes a collection by walking its
// objects with sizes taken from the file; a free-space object of size 0 makes that walk
// stand still (an endless loop inside H5Aread), and an object that runs past its collection
// makes HDF5 copy memory it does not own. No HDF5 call tells the caller where a string's
// collection is before it reads it, but every read passes through the file driver, which
// sees the collection's bytes first: this one refuses the read (so HDF5 returns an error)
// when the collection's walk would not end inside it.
//
// Likewise version 1 object headers (the default format's, h5py's), which carry no checksum:
// HDF5 1.10.8 decodes an attribute or dataspace message with the sizes its fields declare,
// without comparing them with the message's own size, so a damaged field makes it copy
// memory it does not own. The driver sees each object header chunk as it is read (the
// chunks' addresses from their continuation messages) and refuses one holding such a
// message, or an attribute whose variable-length value (a string's text) does not name an
// object of its declared size in a global heap collection of the file: HDF5 looks the object
// up without a bound (a segfault) and allocates what the value's length declares (gigabytes
// cleared for a damaged one). Version 2 headers carry a checksum HDF5 verifies first, after
// it has allocated the size they declare: a header whose chunk runs past the file's
// addresses (either version) is refused at its first bytes.
// docs/robustness.md.
#include "common/Status.h"

#include <hdf5.h>

#include <cstddef>

namespace hair::hdf5
{

/// A new file-access property list (the caller closes it) that opens files read-only through
/// the checked driver, with at most `metadataReadAttempts` reads of a metadata entry whose
/// checksum fails (HDF5's retries for a file still being written in SWMR mode); -1 if the
/// driver cannot be registered.
hid_t checkedReadAccess(unsigned metadataReadAttempts);

/// Whether `size` bytes that begin with a global heap collection's signature ("GCOL",
/// version 1) and hold its whole declared size are a collection HDF5 can decode: each
/// object's header inside the collection, each object advancing the walk by at least a
/// header and ending inside it. Assumes 8-byte lengths (the reader refuses files with any
/// other). Bytes that do not begin with the signature are not a collection: Ok.
Status checkGlobalHeapCollection(const unsigned char* bytes, std::size_t size);

/// Whether the messages of a version 1 object header chunk (`bytes`, `size` of them, the
/// messages only: the 16-byte prefix of a header's first chunk left out) are ones HDF5 1.10.8
/// can decode without reading past them: each attribute message's name, datatype, dataspace
/// and values, and each dataspace message's dimensions, inside the message (File Format
/// Specification 3.0, IV.A.1.a and IV.A.2.b, .m). Messages that do not fit the chunk, and
/// other kinds, are left to HDF5, which checks those itself. Assumes 8-byte lengths.
/// Variable-length values' references into the global heap are not checked here (that needs
/// the file: the driver checks them as it reads a header).
Status checkObjectHeaderMessages(const unsigned char* bytes, std::size_t size);

} // namespace hair::hdf5
