#include "io/Hdf5.h"

#include <algorithm>
#include <limits>

namespace hair::hdf5
{

void Handle::reset()
{
  if (Id >= 0)
  {
    H5E_BEGIN_TRY
    {
      switch (H5Iget_type(Id))
      {
      case H5I_FILE:
        H5Fclose(Id);
        break;
      case H5I_GROUP:
        H5Gclose(Id);
        break;
      case H5I_DATASET:
        H5Dclose(Id);
        break;
      case H5I_DATASPACE:
        H5Sclose(Id);
        break;
      case H5I_DATATYPE:
        H5Tclose(Id);
        break;
      case H5I_ATTR:
        H5Aclose(Id);
        break;
      case H5I_GENPROP_LST:
        H5Pclose(Id);
        break;
      default:
        break;
      }
    }
    H5E_END_TRY;
  }
  Id = -1;
}

// ---- Attributes -------------------------------------------------------------------------

Status writeStringAttribute(hid_t obj, const char* name, const std::string& value)
{
  // Variable-length UTF-8: h5py reads it as a str, not bytes.
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  Handle space(H5Screate(H5S_SCALAR));
  Handle attr(H5Acreate2(obj, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT));
  const char* text = value.c_str();
  if (!attr.valid() || H5Awrite(attr.get(), type.get(), &text) < 0)
  {
    return Status::Error(std::string("cannot write the attribute ") + name);
  }
  return Status::Ok();
}

namespace
{
/// Whether the attribute holds exactly one value (the readers below read one into a
/// scalar: an attribute of another shape would overrun it).
bool holdsOneValue(hid_t attr)
{
  Handle space(H5Aget_space(attr));
  return space.valid() && H5Sget_simple_extent_npoints(space.get()) == 1;
}
} // namespace

bool readStringAttribute(hid_t obj, const char* name, std::string& value)
{
  if (H5Aexists(obj, name) <= 0)
  {
    return false;
  }
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT));
  if (!attr.valid() || !holdsOneValue(attr.get()))
  {
    return false;
  }
  Handle type(H5Aget_type(attr.get()));
  if (H5Tget_class(type.get()) != H5T_STRING)
  {
    return false;
  }
  if (H5Tis_variable_str(type.get()) > 0)
  {
    char* s = nullptr;
    Handle memType(H5Tcopy(H5T_C_S1));
    H5Tset_size(memType.get(), H5T_VARIABLE);
    H5Tset_cset(memType.get(), H5Tget_cset(type.get()));
    if (H5Aread(attr.get(), memType.get(), &s) < 0 || s == nullptr)
    {
      return false;
    }
    value = s;
    H5free_memory(s);
    return true;
  }
  const std::size_t size = H5Tget_size(type.get());
  std::string buffer(size + 1, '\0');
  Handle memType(H5Tcopy(H5T_C_S1));
  H5Tset_size(memType.get(), size + 1);
  H5Tset_cset(memType.get(), H5Tget_cset(type.get()));
  if (H5Aread(attr.get(), memType.get(), buffer.data()) < 0)
  {
    return false;
  }
  value = buffer.c_str();
  return true;
}

bool readIntAttribute(hid_t obj, const char* name, int& value)
{
  Handle attr(H5Aexists(obj, name) > 0 ? H5Aopen(obj, name, H5P_DEFAULT) : -1);
  return attr.valid() && holdsOneValue(attr.get()) &&
         H5Aread(attr.get(), H5T_NATIVE_INT, &value) >= 0;
}

bool readNumericAttribute(hid_t obj, const char* name, double& value)
{
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT));
  if (!attr.valid() || !holdsOneValue(attr.get()))
  {
    return false;
  }
  Handle type(H5Aget_type(attr.get()));
  const H5T_class_t typeClass = H5Tget_class(type.get());
  if (typeClass != H5T_FLOAT && typeClass != H5T_INTEGER)
  {
    return false;
  }
  double read = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &read) < 0)
  {
    return false;
  }
  value = read;
  return true;
}

std::vector<std::string> attributeNames(hid_t obj)
{
  std::vector<std::string> names;
  H5Aiterate2(
      obj, H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t
      {
        static_cast<std::vector<std::string>*>(data)->push_back(name);
        return 0;
      },
      &names);
  return names;
}

// ---- Groups -----------------------------------------------------------------------------

bool linkNames(hid_t group, std::vector<std::string>& names)
{
  names.clear();
  H5G_info_t info{};
  if (H5Gget_info(group, &info) < 0)
  {
    return false;
  }
  for (hsize_t k = 0; k < info.nlinks; ++k)
  {
    char name[256] = {0};
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof(name), H5P_DEFAULT);
    names.push_back(name);
  }
  return true;
}

// ---- Datasets ---------------------------------------------------------------------------

bool writeArray(hid_t parent, const char* name, hid_t type, hsize_t count, const void* data,
                bool write)
{
  Handle space(H5Screate_simple(1, &count, nullptr));
  Handle d(H5Dcreate2(parent, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  return d.valid() && (!write || H5Dwrite(d.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0);
}

bool writeRows(hid_t parent, const char* name, hsize_t rows, hsize_t columns, const double* data,
               bool write)
{
  const hsize_t dims[2] = {rows, columns};
  Handle space(H5Screate_simple(2, dims, nullptr));
  Handle d(H5Dcreate2(parent, name, H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT, H5P_DEFAULT,
                      H5P_DEFAULT));
  return d.valid() &&
         (!write || H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0);
}

Handle createGrowing(hid_t parent, const char* name, const std::vector<hsize_t>& frameShape)
{
  std::vector<hsize_t> dims{0}, maxDims{H5S_UNLIMITED}, chunk{1};
  for (hsize_t d : frameShape)
  {
    dims.push_back(d);
    maxDims.push_back(d);
    chunk.push_back(std::max<hsize_t>(d, 1));
  }
  if (frameShape.empty())
  {
    chunk[0] = 1024; // scalars per frame: chunks of many frames
  }
  Handle space(H5Screate_simple(int(dims.size()), dims.data(), maxDims.data()));
  Handle props(H5Pcreate(H5P_DATASET_CREATE));
  H5Pset_chunk(props.get(), int(chunk.size()), chunk.data());
  return Handle(H5Dcreate2(parent, name, H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT, props.get(),
                           H5P_DEFAULT));
}

bool appendSlab(hid_t dataset, hsize_t t, const double* data)
{
  Handle space(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  dims[0] = t + 1;
  if (H5Dset_extent(dataset, dims.data()) < 0)
  {
    return false;
  }
  Handle fileSpace(H5Dget_space(dataset));
  std::vector<hsize_t> start(rank, 0), count = dims;
  start[0] = t;
  count[0] = 1;
  H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                      nullptr);
  Handle memSpace(H5Screate_simple(rank, count.data(), nullptr));
  return H5Dwrite(dataset, H5T_NATIVE_DOUBLE, memSpace.get(), fileSpace.get(), H5P_DEFAULT, data) >=
         0;
}

bool readSlab(hid_t dataset, hsize_t t, std::vector<double>& data)
{
  Handle fileSpace(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(fileSpace.get());
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(fileSpace.get(), dims.data(), nullptr);
  if (rank < 1 || dims[0] <= t)
  {
    return false;
  }
  std::vector<hsize_t> start(rank, 0), count = dims;
  start[0] = t;
  count[0] = 1;
  hsize_t n = 1;
  for (int k = 1; k < rank; ++k)
  {
    n *= dims[k];
  }
  data.resize(n);
  H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                      nullptr);
  Handle memSpace(H5Screate_simple(rank, count.data(), nullptr));
  return H5Dread(dataset, H5T_NATIVE_DOUBLE, memSpace.get(), fileSpace.get(), H5P_DEFAULT,
                 data.data()) >= 0;
}

Handle createFixed(hid_t parent, const char* name, hsize_t frames,
                   const std::vector<hsize_t>& frameShape, bool fill)
{
  std::vector<hsize_t> dims{frames};
  dims.insert(dims.end(), frameShape.begin(), frameShape.end());
  Handle space(H5Screate_simple(int(dims.size()), dims.data(), nullptr));
  Handle props(H5Pcreate(H5P_DATASET_CREATE));
  H5Pset_layout(props.get(), H5D_CONTIGUOUS);
  H5Pset_alloc_time(props.get(), H5D_ALLOC_TIME_EARLY);
  // No times in the object header: nothing there to change after it is created.
  H5Pset_obj_track_times(props.get(), 0);
  if (fill)
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    H5Pset_fill_value(props.get(), H5T_NATIVE_DOUBLE, &nan);
    H5Pset_fill_time(props.get(), H5D_FILL_TIME_ALLOC);
  }
  else
  {
    H5Pset_fill_time(props.get(), H5D_FILL_TIME_NEVER);
  }
  return Handle(H5Dcreate2(parent, name, H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT, props.get(),
                           H5P_DEFAULT));
}

bool RowSelection::build(hid_t dataset, const Runs& runs)
{
  file = Handle(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(file.get());
  if (rank < 2)
  {
    return false;
  }
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(file.get(), dims.data(), nullptr);
  hsize_t perRow = 1;
  for (int k = 2; k < rank; ++k)
  {
    perRow *= dims[k];
  }
  Rows = runs;
  values = 0;
  for (const auto& run : runs)
  {
    values += run.second * perRow;
  }
  const hsize_t n = std::max<hsize_t>(values, 1);
  memory = Handle(H5Screate_simple(1, &n, nullptr));
  if (values == 0)
  {
    H5Sselect_none(memory.get());
  }
  return file.valid() && memory.valid() && select(0);
}

bool RowSelection::moveToFrame(hsize_t t)
{
  return t == Frame || select(t);
}

bool RowSelection::select(hsize_t t)
{
  const int rank = H5Sget_simple_extent_ndims(file.get());
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(file.get(), dims.data(), nullptr);
  H5Sselect_none(file.get());
  std::vector<hsize_t> start(rank, 0), count = dims;
  start[0] = t;
  count[0] = 1;
  for (const auto& [first, rows] : Rows)
  {
    start[1] = first;
    count[1] = rows;
    if (H5Sselect_hyperslab(file.get(), H5S_SELECT_OR, start.data(), nullptr, count.data(),
                            nullptr) < 0)
    {
      return false;
    }
  }
  Frame = t;
  return true;
}

bool readFirst(hid_t dataset, hsize_t count, double* data)
{
  Handle fileSpace(H5Dget_space(dataset));
  const hsize_t start = 0;
  H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, &start, nullptr, &count, nullptr);
  Handle memSpace(H5Screate_simple(1, &count, nullptr));
  return H5Dread(dataset, H5T_NATIVE_DOUBLE, memSpace.get(), fileSpace.get(), H5P_DEFAULT, data) >=
         0;
}

std::vector<hsize_t> extent(hid_t dataset)
{
  Handle space(H5Dget_space(dataset));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> dims(std::max(rank, 0));
  if (rank > 0)
  {
    H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  }
  return dims;
}

bool readWhole(hid_t dataset, hid_t memType, void* data)
{
  return H5Dread(dataset, memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
}

} // namespace hair::hdf5
