#pragma once
// The small part of HDF5's C API that the state file uses, wrapped: a handle that closes
// itself, attributes, datasets that grow by one frame, and whole or partial reads. Every
// function reports failure by its result; HDF5 also prints its error stack unless the caller
// silences it (H5E_BEGIN_TRY … H5E_END_TRY), which Handle::reset() always does.
#include "common/Status.h"

#include <hdf5.h>

#include <string>
#include <vector>

namespace hair::hdf5
{

/// Closes an HDF5 handle of any kind when it goes out of scope.
class Handle
{
public:
  Handle() = default;
  explicit Handle(hid_t id) : Id(id) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : Id(o.Id) { o.Id = -1; }
  Handle& operator=(Handle&& o) noexcept
  {
    reset();
    Id = o.Id;
    o.Id = -1;
    return *this;
  }
  ~Handle() { reset(); }
  void reset();
  hid_t get() const { return Id; }
  bool valid() const { return Id >= 0; }

private:
  hid_t Id = -1;
};

// ---- Attributes -------------------------------------------------------------------------

/// A scalar string attribute, variable-length UTF-8.
Status writeStringAttribute(hid_t obj, const char* name, const std::string& value);

/// A scalar numeric attribute of the file type `type`, written from `value`.
template <typename T>
Status writeScalarAttribute(hid_t obj, const char* name, hid_t type, T value)
{
  Handle space(H5Screate(H5S_SCALAR));
  Handle attr(H5Acreate2(obj, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT));
  if (!attr.valid() || H5Awrite(attr.get(), type, &value) < 0)
  {
    return Status::Error(std::string("cannot write the attribute ") + name);
  }
  return Status::Ok();
}

/// A string attribute holding one string, of fixed or variable length. Refused (with what
/// is wrong: missing, of another shape or class, unreadable) otherwise; `value` is then
/// untouched.
Status readStringAttribute(hid_t obj, const char* name, std::string& value);

/// An integer attribute holding one value that fits an int. Refused (with what is wrong)
/// otherwise; `value` is then untouched.
Status readIntAttribute(hid_t obj, const char* name, int& value);

/// An integer or floating-point attribute read as a double. False (and `value` untouched) if
/// it is of another class or cannot be read.
bool readNumericAttribute(hid_t obj, const char* name, double& value);

/// The names of an object's attributes, in name order. False (and no names) if they cannot
/// be listed (an attribute message HDF5 cannot decode) or there are more than MaxLinks.
bool attributeNames(hid_t obj, std::vector<std::string>& names);

// ---- Groups -----------------------------------------------------------------------------

/// The most links linkNames lists: a state file's groups hold tens; a damaged one may claim
/// billions.
inline constexpr hsize_t MaxLinks = 100000;

/// The names of a group's links, in name order. False (and no names) if they cannot be
/// listed or there are more than MaxLinks.
bool linkNames(hid_t group, std::vector<std::string>& names);

// ---- Datasets ---------------------------------------------------------------------------

/// Creates a 1-D dataset of `count` values of `type` and writes them (`write` false: only
/// creates it; in a file several MPI ranks create together, one writes). False if either
/// fails.
bool writeArray(hid_t parent, const char* name, hid_t type, hsize_t count, const void* data,
                bool write = true);

/// Creates a 2-D dataset of `rows` × `columns` doubles (row-major) and writes them.
bool writeRows(hid_t parent, const char* name, hsize_t rows, hsize_t columns, const double* data,
               bool write = true);

/// A dataset of `type` (doubles unless said) that grows by one frame along its first
/// dimension, each frame shaped `frameShape` (empty: one scalar per frame).
Handle createGrowing(hid_t parent, const char* name, const std::vector<hsize_t>& frameShape,
                     hid_t type = H5T_NATIVE_DOUBLE);

/// Writes one frame's slab at index t from `data` of `memType`, growing the dataset to t + 1
/// frames first.
bool appendSlab(hid_t dataset, hsize_t t, const void* data, hid_t memType = H5T_NATIVE_DOUBLE);

/// Reads frame t of a dataset of frames (all but the first dimension, flattened).
bool readSlab(hid_t dataset, hsize_t t, std::vector<double>& data);

/// A dataset of `type` (doubles unless said) with room for `frames` frames from the start, each
/// shaped `frameShape` (empty: one scalar per frame), stored contiguously and allocated when it is
/// created: writing a frame then writes its raw data only, never the file's structure
/// (what the state file written by several ranks relies on, docs/state-file.md). `fill`:
/// the file holds NaN where no frame was written (set for small datasets; writing it costs
/// the whole dataset once); else whatever the disk had (zeros on a new file).
Handle createFixed(hid_t parent, const char* name, hsize_t frames,
                   const std::vector<hsize_t>& frameShape, bool fill,
                   hid_t type = H5T_NATIVE_DOUBLE);

/// Runs of consecutive rows of a dataset's second dimension: (first row, row count).
using Runs = std::vector<std::pair<hsize_t, hsize_t>>;

/// The file space of `dataset` ([T, N, …]) with frame t's rows `runs` selected, whole in
/// the other dimensions (no runs: nothing selected), and a memory space of as many values,
/// contiguous. Built for frame 0, selected again for another frame by moveToFrame (HDF5
/// 1.10's H5Soffset_simple would do it in one call, but its collective MPI-IO writes ignore
/// the offset: every frame landed on frame 0).
struct RowSelection
{
  Handle file, memory;
  hsize_t values = 0;
  bool build(hid_t dataset, const Runs& runs);
  bool moveToFrame(hsize_t t);

private:
  Runs Rows;
  hsize_t Frame = 0;
  bool select(hsize_t t);
};

/// Reads the first `count` values of a 1-D dataset as doubles.
bool readFirst(hid_t dataset, hsize_t count, double* data);

/// A dataset's dimensions (empty for a scalar or an invalid dataset).
std::vector<hsize_t> extent(hid_t dataset);

/// What a dataset's metadata say, read without reading its data: enough to decide whether
/// reading it is sensible before anything is allocated.
struct DatasetInfo
{
  H5T_class_t typeClass = H5T_NO_CLASS;
  std::size_t typeSize = 0;  ///< bytes per value in the file
  std::vector<hsize_t> dims; ///< empty for a scalar
  bool simple = false;       ///< a simple dataspace (not null, not scalar)
  int filters = 0;           ///< filters in its pipeline (compression, …)
  hsize_t chunkValues = 0;   ///< values per chunk (0: not chunked)
  /// A contiguous or compact dataset's storage holds exactly its values. False for one never
  /// written or a damaged layout whose size disagrees with the dataspace (HDF5 1.10.8 reads
  /// past its buffer then).
  bool storageMatches = true;
};
/// False if the dataset's type, space or creation properties cannot be read.
bool describe(hid_t dataset, DatasetInfo& info);

/// Reads a whole dataset as `memType`.
bool readWhole(hid_t dataset, hid_t memType, void* data);

} // namespace hair::hdf5
