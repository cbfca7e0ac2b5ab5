#include "io/CheckedReadDriver.h"

#include <H5FDpublic.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <new>
#include <string>
#include <vector>

namespace hair::hdf5
{
namespace
{

// The global heap collection's layout (HDF5 File Format Specification 3.0, section III.E,
// "Global Heap"): "GCOL", version 1, 3 reserved bytes, the collection's size (a length);
// then objects, each a 2-byte index, a 2-byte reference count, 4 reserved bytes and its size
// (a length), its data padded to a multiple of 8. Object 0 is the free space, whose size
// counts its own header. With 8-byte lengths both headers are 16 bytes.
constexpr std::size_t HeaderBytes = 16;
constexpr std::size_t ObjectHeaderBytes = 16;
// A collection larger than this is refused rather than read twice: HDF5 sizes a collection
// to its largest object (at least 4 KiB); a state file's hold a few short strings.
constexpr std::uint64_t LargestCollection = std::uint64_t(256) << 20;

std::uint64_t little(const unsigned char* p, int bytes)
{
  std::uint64_t v = 0;
  for (int k = bytes - 1; k >= 0; --k)
  {
    v = (v << 8) | p[k];
  }
  return v;
}

bool isCollection(const unsigned char* p, std::size_t size)
{
  return size >= HeaderBytes && std::memcmp(p, "GCOL", 4) == 0 && p[4] == 1;
}

// The largest address a file offset (off_t, signed 64-bit) can hold.
constexpr haddr_t MaxAddress = (haddr_t(1) << 63) - 1;

struct CheckedFile
{
  H5FD_t Public; // first: HDF5 sees a CheckedFile as its H5FD_t
  int Descriptor = -1;
  haddr_t EndOfAddresses = 0;
  dev_t Device = 0;
  ino_t Inode = 0;
};

CheckedFile* self(H5FD_t* f)
{
  return reinterpret_cast<CheckedFile*>(f);
}
const CheckedFile* self(const H5FD_t* f)
{
  return reinterpret_cast<const CheckedFile*>(f);
}

/// Reads `size` bytes at `offset`; bytes past the end of the file read as zeros (as HDF5's
/// default driver does). False on a read error.
bool readAt(int fd, std::uint64_t offset, std::size_t size, unsigned char* out)
{
  while (size > 0)
  {
    const ssize_t n = ::pread(fd, out, size, off_t(offset));
    if (n < 0)
    {
      if (errno == EINTR)
      {
        continue;
      }
      return false;
    }
    if (n == 0)
    {
      std::memset(out, 0, size);
      return true;
    }
    out += n;
    offset += std::uint64_t(n);
    size -= std::size_t(n);
  }
  return true;
}

H5FD_t* openChecked(const char* name, unsigned flags, hid_t, haddr_t maxaddr)
{
  // Read-only: HairDynamics writes through HDF5's own drivers.
  if ((flags & (H5F_ACC_RDWR | H5F_ACC_TRUNC | H5F_ACC_CREAT | H5F_ACC_EXCL)) != 0 ||
      name == nullptr || maxaddr == 0 || maxaddr == HADDR_UNDEF || maxaddr > MaxAddress)
  {
    return nullptr;
  }
  const int fd = ::open(name, O_RDONLY | O_CLOEXEC);
  if (fd < 0)
  {
    return nullptr;
  }
  struct stat info;
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode))
  {
    ::close(fd);
    return nullptr;
  }
  auto* f = new (std::nothrow) CheckedFile;
  if (f == nullptr)
  {
    ::close(fd);
    return nullptr;
  }
  std::memset(&f->Public, 0, sizeof(f->Public));
  f->Descriptor = fd;
  f->Device = info.st_dev;
  f->Inode = info.st_ino;
  return &f->Public;
}

herr_t closeChecked(H5FD_t* file)
{
  CheckedFile* f = self(file);
  const int rc = ::close(f->Descriptor);
  delete f;
  return rc == 0 ? 0 : -1;
}

/// One open file per file on disk (HDF5 shares it among the handles that open it).
int compareChecked(const H5FD_t* a, const H5FD_t* b)
{
  const CheckedFile* x = self(a);
  const CheckedFile* y = self(b);
  if (x->Device != y->Device)
  {
    return x->Device < y->Device ? -1 : 1;
  }
  if (x->Inode != y->Inode)
  {
    return x->Inode < y->Inode ? -1 : 1;
  }
  return 0;
}

herr_t queryChecked(const H5FD_t*, unsigned long* flags)
{
  // What HDF5's POSIX driver declares, SWMR reading included.
  *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_ACCUMULATE_METADATA | H5FD_FEAT_DATA_SIEVE |
           H5FD_FEAT_AGGREGATE_SMALLDATA | H5FD_FEAT_POSIX_COMPAT_HANDLE |
           H5FD_FEAT_SUPPORTS_SWMR_IO | H5FD_FEAT_DEFAULT_VFD_COMPATIBLE;
  return 0;
}

haddr_t endOfAddresses(const H5FD_t* file, H5FD_mem_t)
{
  return self(file)->EndOfAddresses;
}

herr_t setEndOfAddresses(H5FD_t* file, H5FD_mem_t, haddr_t addr)
{
  if (addr > MaxAddress)
  {
    return -1;
  }
  self(file)->EndOfAddresses = addr;
  return 0;
}

/// The file's size now: a file being written grows while it is read.
haddr_t endOfFile(const H5FD_t* file, H5FD_mem_t)
{
  struct stat info;
  if (::fstat(self(file)->Descriptor, &info) != 0)
  {
    return HADDR_UNDEF;
  }
  return haddr_t(info.st_size);
}

herr_t handleChecked(H5FD_t* file, hid_t, void** handle)
{
  if (handle == nullptr)
  {
    return -1;
  }
  *handle = &self(file)->Descriptor;
  return 0;
}

herr_t readChecked(H5FD_t* file, H5FD_mem_t, hid_t, haddr_t addr, size_t size, void* buffer)
{
  CheckedFile* f = self(file);
  auto* bytes = static_cast<unsigned char*>(buffer);
  if (addr == HADDR_UNDEF || addr > MaxAddress || size > MaxAddress - addr ||
      addr + size > f->EndOfAddresses || !readAt(f->Descriptor, addr, size, bytes))
  {
    return -1;
  }
  if (!isCollection(bytes, size))
  {
    return 0;
  }
  // A global heap collection: HDF5 reads its first 4 KiB, then the rest after it, and walks
  // it only once it has all of it, so a larger collection is read whole here and checked.
  const std::uint64_t whole = little(bytes + 8, 8);
  if (whole <= size)
  {
    return checkGlobalHeapCollection(bytes, size) ? 0 : -1;
  }
  const haddr_t end = endOfFile(file, H5FD_MEM_DEFAULT);
  if (end == HADDR_UNDEF || addr > end || whole > end - addr || whole > LargestCollection)
  {
    return -1;
  }
  std::vector<unsigned char> collection;
  try
  {
    collection.resize(std::size_t(whole));
  }
  catch (const std::bad_alloc&)
  {
    return -1;
  }
  if (!readAt(f->Descriptor, addr, collection.size(), collection.data()))
  {
    return -1;
  }
  return checkGlobalHeapCollection(collection.data(), collection.size()) ? 0 : -1;
}

herr_t writeChecked(H5FD_t*, H5FD_mem_t, hid_t, haddr_t, size_t, const void*)
{
  return -1;
}

herr_t nothing(H5FD_t*, hid_t, hbool_t)
{
  return 0;
}

// A reader takes no lock: it excludes no one, and a writer in SWMR mode holds none.
herr_t lockChecked(H5FD_t*, hbool_t)
{
  return 0;
}
herr_t unlockChecked(H5FD_t*)
{
  return 0;
}

H5FD_class_t makeClass()
{
  H5FD_class_t c;
  std::memset(&c, 0, sizeof(c));
  c.name = "hairdynamics-checked-read";
  c.maxaddr = MaxAddress;
  c.fc_degree = H5F_CLOSE_WEAK;
  c.open = openChecked;
  c.close = closeChecked;
  c.cmp = compareChecked;
  c.query = queryChecked;
  c.get_eoa = endOfAddresses;
  c.set_eoa = setEndOfAddresses;
  c.get_eof = endOfFile;
  c.get_handle = handleChecked;
  c.read = readChecked;
  c.write = writeChecked;
  c.flush = nothing;
  c.truncate = nothing;
  c.lock = lockChecked;
  c.unlock = unlockChecked;
  const H5FD_mem_t dichotomy[H5FD_MEM_NTYPES] = H5FD_FLMAP_DICHOTOMY;
  std::memcpy(c.fl_map, dichotomy, sizeof(dichotomy));
  return c;
}

hid_t driver()
{
  static const H5FD_class_t cls = makeClass();
  static const hid_t id = H5FDregister(&cls);
  return id;
}

} // namespace

Status checkGlobalHeapCollection(const unsigned char* bytes, std::size_t size)
{
  if (!isCollection(bytes, size))
  {
    return Status::Ok();
  }
  const std::uint64_t whole = little(bytes + 8, 8);
  if (whole > size)
  {
    return Status::Error("a global heap collection declares " + std::to_string(whole) +
                         " bytes where " + std::to_string(size) + " are given");
  }
  std::uint64_t at = HeaderBytes;
  while (at < whole)
  {
    if (whole - at < ObjectHeaderBytes)
    {
      break; // too short for an object: free space, as HDF5 reads it
    }
    const unsigned index = unsigned(little(bytes + at, 2));
    const std::uint64_t objectSize = little(bytes + at + 8, 8);
    const std::uint64_t room = whole - at;
    // HDF5 advances by the header and the padded data for an object, by the size alone
    // (which counts the header) for the free space.
    const bool dataFits = index == 0 || objectSize <= room - ObjectHeaderBytes;
    const std::uint64_t step =
        index > 0 ? ObjectHeaderBytes + ((objectSize + 7) & ~std::uint64_t(7)) : objectSize;
    if (!dataFits || step < ObjectHeaderBytes || step > room)
    {
      return Status::Error("a global heap collection's object " + std::to_string(index) +
                           " at byte " + std::to_string(at) + " of it has size " +
                           std::to_string(objectSize) + ", which does not fit the collection");
    }
    at += step;
  }
  return Status::Ok();
}

hid_t checkedReadAccess(unsigned metadataReadAttempts)
{
  const hid_t id = driver();
  if (id < 0)
  {
    return -1;
  }
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  if (fapl < 0 || H5Pset_driver(fapl, id, nullptr) < 0 ||
      H5Pset_metadata_read_attempts(fapl, metadataReadAttempts) < 0)
  {
    if (fapl >= 0)
    {
      H5Pclose(fapl);
    }
    return -1;
  }
  return fapl;
}

} // namespace hair::hdf5
