#include "io/CheckedReadDriver.h"

#include <H5FDpublic.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <map>
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

// Version 1 object headers (File Format Specification 3.0, IV.A.1.a): a 16-byte prefix
// (version 1, a reserved byte, the message count, the reference count, the first chunk's
// size, padding), then messages, each an 8-byte header (type, size, flags, 3 reserved bytes)
// and its data; further chunks hold messages only, found by continuation messages.
constexpr std::size_t PrefixBytes = 16;
constexpr std::size_t MessageHeaderBytes = 8;
constexpr unsigned DataspaceMessage = 0x0001;
constexpr unsigned AttributeMessage = 0x000C;
constexpr unsigned ContinuationMessage = 0x0010;
constexpr unsigned SharedMessageFlag = 0x02;
constexpr unsigned MaxRank = 32; // H5S_MAX_RANK
constexpr unsigned VariableLengthClass = 9;
constexpr std::size_t HeapReferenceBytes = 16;

std::uint64_t alignedTo8(std::uint64_t n)
{
  return (n + 7) & ~std::uint64_t(7);
}

/// A dataspace message's data (IV.A.2.b), `size` bytes: its dimensions inside it. Sets the
/// number of elements (0 for a null dataspace, 1 for a scalar).
Status checkDataspace(const unsigned char* d, std::size_t size, std::uint64_t& elements)
{
  if (size < 4)
  {
    return Status::Error("a dataspace message of " + std::to_string(size) + " bytes");
  }
  const unsigned version = d[0];
  const unsigned rank = d[1];
  const unsigned flags = d[2];
  if (version != 1 && version != 2)
  {
    return Status::Error("a dataspace message of version " + std::to_string(version));
  }
  if (rank > MaxRank)
  {
    return Status::Error("a dataspace of rank " + std::to_string(rank));
  }
  const std::size_t header = version == 1 ? 8 : 4;
  const std::size_t needed = header + std::size_t(rank) * 8 * ((flags & 1) != 0 ? 2 : 1);
  if (needed > size)
  {
    return Status::Error("a dataspace message of rank " + std::to_string(rank) + " needs " +
                         std::to_string(needed) + " bytes and has " + std::to_string(size));
  }
  const unsigned kind = version == 1 ? (rank == 0 ? 0 : 1) : d[3];
  elements = kind == 0 ? 1 : 0;
  if (kind == 1)
  {
    elements = 1;
    for (unsigned k = 0; k < rank; ++k)
    {
      const std::uint64_t n = little(d + header + 8 * k, 8);
      if (n != 0 && elements > ~std::uint64_t(0) / n)
      {
        return Status::Error("a dataspace whose element count overflows");
      }
      elements *= n;
    }
  }
  return Status::Ok();
}

/// An attribute message's data (IV.A.2.m), `size` bytes: its name (with its terminating
/// zero), datatype, dataspace and, for numbers and strings, its values inside it. For a
/// variable-length type, also each value's reference into the global heap (a sequence length,
/// then a collection's address and an object's index: III.E, IV.A.2.d), which `heapObject`
/// checks (address, index, bytes the length declares) against the collection in the file.
template <typename HeapObject>
Status checkAttribute(const unsigned char* d, std::size_t size, HeapObject&& heapObject)
{
  if (size < 8)
  {
    return Status::Error("an attribute message of " + std::to_string(size) + " bytes");
  }
  const unsigned version = d[0];
  const unsigned flags = version == 1 ? 0 : d[1];
  const std::uint64_t nameBytes = little(d + 2, 2);
  const std::uint64_t typeBytes = little(d + 4, 2);
  const std::uint64_t spaceBytes = little(d + 6, 2);
  if (version < 1 || version > 3)
  {
    return Status::Error("an attribute message of version " + std::to_string(version));
  }
  const std::uint64_t header = version == 3 ? 9 : 8;
  const auto padded = [&](std::uint64_t n) { return version == 1 ? alignedTo8(n) : n; };
  const std::uint64_t typeAt = header + padded(nameBytes);
  const std::uint64_t spaceAt = typeAt + padded(typeBytes);
  const std::uint64_t valuesAt = spaceAt + padded(spaceBytes);
  if (nameBytes == 0 || typeBytes < 8 || valuesAt > size ||
      std::memchr(d + header, 0, std::size_t(nameBytes)) == nullptr)
  {
    return Status::Error("an attribute message of " + std::to_string(size) +
                         " bytes declares a name of " + std::to_string(nameBytes) +
                         ", a datatype of " + std::to_string(typeBytes) + " and a dataspace of " +
                         std::to_string(spaceBytes) + " bytes");
  }
  // Shared datatypes or dataspaces are references to other messages, read on their own.
  if ((flags & 0x03) != 0)
  {
    return Status::Ok();
  }
  std::uint64_t elements = 0;
  if (Status s = checkDataspace(d + spaceAt, std::size_t(spaceBytes), elements); !s)
  {
    return Status::Error("an attribute's " + s.message());
  }
  // Fixed-point numbers, floating-point numbers and strings: the values are the element
  // size (the datatype's bytes 4-7) times the count. Variable-length sequences and strings:
  // each value a heap reference (below). Other classes are left to HDF5.
  const unsigned typeClass = d[typeAt] & 0x0f;
  if (typeClass == VariableLengthClass)
  {
    // The datatype: its 8-byte header, then the base type's (its size at bytes 4-7). Each
    // value: a 4-byte sequence length, an 8-byte collection address, a 4-byte object index.
    // HDF5 1.10.8 allocates and clears length × base size bytes, then copies the object's
    // bytes in whatever its size, and looks the index up without comparing it with the
    // collection's objects: a damaged length made it clear gigabytes for 20 s, a damaged
    // index or a smaller sequence made it copy memory it does not own (a segfault in
    // H5HG_read). What HDF5 writes: the object holds exactly length × base size bytes (none
    // when the address is 0, an empty sequence).
    if (typeBytes < 16)
    {
      return Status::Error("a variable-length datatype of " + std::to_string(typeBytes) + " bytes");
    }
    const std::uint64_t base = little(d + typeAt + 12, 4);
    const std::uint64_t room = size - valuesAt;
    if (elements > room / HeapReferenceBytes)
    {
      return Status::Error("an attribute of " + std::to_string(elements) +
                           " variable-length values in " + std::to_string(room) + " bytes");
    }
    for (std::uint64_t k = 0; k < elements; ++k)
    {
      const unsigned char* v = d + valuesAt + k * HeapReferenceBytes;
      const std::uint64_t length = little(v, 4);
      const std::uint64_t address = little(v + 4, 8);
      const std::uint64_t index = little(v + 12, 4);
      if (address == 0 && length == 0)
      {
        continue;
      }
      if (Status s = heapObject(address, index, length * base); !s)
      {
        return Status::Error("an attribute's value " + std::to_string(k) + " of " +
                             std::to_string(length) + " * " + std::to_string(base) +
                             " bytes: " + s.message());
      }
    }
  }
  if (typeClass == 0 || typeClass == 1 || typeClass == 3)
  {
    const std::uint64_t element = little(d + typeAt + 4, 4);
    const std::uint64_t room = size - valuesAt;
    if (element != 0 && elements > room / element)
    {
      return Status::Error("an attribute of " + std::to_string(elements) + " values of " +
                           std::to_string(element) + " bytes in " + std::to_string(room) +
                           " bytes");
    }
  }
  return Status::Ok();
}

/// Walks a version 1 chunk's messages (see checkObjectHeaderMessages), handing each
/// continuation message's chunk (address, length) to `continuation`, which says whether the
/// chunk can be in the file.
template <typename Continuation, typename HeapObject>
Status walkMessages(const unsigned char* bytes, std::size_t size, Continuation&& continuation,
                    HeapObject&& heapObject)
{
  std::size_t at = 0;
  while (size - at >= MessageHeaderBytes)
  {
    const unsigned type = unsigned(little(bytes + at, 2));
    const std::size_t length = std::size_t(little(bytes + at + 2, 2));
    const unsigned flags = bytes[at + 4];
    const unsigned char* d = bytes + at + MessageHeaderBytes;
    if (length > size - at - MessageHeaderBytes)
    {
      break; // past the bytes given: HDF5 checks a message against its chunk itself
    }
    if ((flags & SharedMessageFlag) == 0)
    {
      Status s = Status::Ok();
      std::uint64_t elements = 0;
      if (type == DataspaceMessage)
      {
        s = checkDataspace(d, length, elements);
      }
      else if (type == AttributeMessage)
      {
        s = checkAttribute(d, length, heapObject);
      }
      else if (type == ContinuationMessage && length >= 16 &&
               !continuation(little(d, 8), little(d + 8, 8)))
      {
        s = Status::Error("a continuation chunk past the end of the file's addresses");
      }
      if (!s)
      {
        return Status::Error("an object header's message at byte " + std::to_string(at) + ": " +
                             s.message());
      }
    }
    at += MessageHeaderBytes + length;
  }
  return Status::Ok();
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
  // Version 1 object header chunks after a header's first, by address: their lengths.
  std::map<haddr_t, std::uint64_t> Continuations;
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
  // What HDF5's POSIX driver declares, SWMR reading included, but the metadata accumulator:
  // with it HDF5 merges neighbouring metadata reads, and the object header check needs each
  // chunk read at its own address.
  *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_DATA_SIEVE | H5FD_FEAT_AGGREGATE_SMALLDATA |
           H5FD_FEAT_POSIX_COMPAT_HANDLE | H5FD_FEAT_SUPPORTS_SWMR_IO |
           H5FD_FEAT_DEFAULT_VFD_COMPATIBLE;
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

/// The size of object `index` (not 0, the free space) of a collection `checkGlobalHeapCollection`
/// accepted, `whole` bytes; false if it holds no such object.
bool findHeapObject(const unsigned char* bytes, std::uint64_t whole, std::uint64_t index,
                    std::uint64_t& objectSize)
{
  std::uint64_t at = HeaderBytes;
  while (at < whole && whole - at >= ObjectHeaderBytes)
  {
    const unsigned i = unsigned(little(bytes + at, 2));
    const std::uint64_t n = little(bytes + at + 8, 8);
    if (i != 0 && i == index)
    {
      objectSize = n;
      return true;
    }
    at += i > 0 ? ObjectHeaderBytes + ((n + 7) & ~std::uint64_t(7)) : n;
  }
  return false;
}

/// Whether the collection at `address` in the file holds object `index` of `bytes` bytes:
/// the collection read here (HDF5 reads it only when it decodes the value), checked as the
/// driver checks every collection, and the object looked up.
Status heapObjectIn(const CheckedFile& f, std::uint64_t address, std::uint64_t index,
                    std::uint64_t bytes)
{
  const std::string where = "object " + std::to_string(index) +
                            " of the global heap collection at " + std::to_string(address);
  const haddr_t end = endOfFile(&f.Public, H5FD_MEM_DEFAULT);
  unsigned char header[HeaderBytes];
  if (end == HADDR_UNDEF || address > end || end - address < HeaderBytes ||
      !readAt(f.Descriptor, address, HeaderBytes, header) || !isCollection(header, HeaderBytes))
  {
    return Status::Error(where + ": no collection there");
  }
  const std::uint64_t whole = little(header + 8, 8);
  if (whole < HeaderBytes || whole > LargestCollection || whole > end - address)
  {
    return Status::Error(where + ": a collection of " + std::to_string(whole) + " bytes");
  }
  std::vector<unsigned char> collection(std::size_t(whole), 0);
  if (!readAt(f.Descriptor, address, collection.size(), collection.data()))
  {
    return Status::Error(where + ": unreadable");
  }
  if (Status s = checkGlobalHeapCollection(collection.data(), collection.size()); !s)
  {
    return Status::Error(where + ": " + s.message());
  }
  std::uint64_t objectSize = 0;
  if (index == 0 || !findHeapObject(collection.data(), whole, index, objectSize))
  {
    return Status::Error(where + ": no such object");
  }
  if (objectSize != bytes)
  {
    return Status::Error(where + " holds " + std::to_string(objectSize) + " bytes");
  }
  return Status::Ok();
}

/// A version 1 object header's chunk, read at `addr`: its messages checked, its continuation
/// chunks remembered. A chunk HDF5 reads in two steps (its first 512 bytes, then all of it) is
/// checked as far as each read goes.
bool checkObjectHeaderRead(CheckedFile& f, haddr_t addr, const unsigned char* bytes,
                           std::size_t size)
{
  // A chunk must lie inside the file's addresses, or HDF5's read of it fails here anyway; but
  // HDF5 1.10.8 allocates a chunk's declared size first, each of the file's metadata read
  // attempts: a damaged size of 4 GB took 43 s of allocations under AddressSanitizer. A chunk
  // whose size runs past the addresses is refused at its first bytes instead.
  const auto inFile = [&f](std::uint64_t at, std::uint64_t length)
  { return at <= f.EndOfAddresses && length <= f.EndOfAddresses - at; };
  const auto remember = [&f, &inFile](std::uint64_t at, std::uint64_t length)
  {
    f.Continuations[haddr_t(at)] = length;
    return inFile(at, length);
  };
  const auto heapObject = [&f](std::uint64_t address, std::uint64_t index, std::uint64_t bytes)
  { return heapObjectIn(f, address, index, bytes); };
  const auto found = f.Continuations.find(addr);
  if (found != f.Continuations.end())
  {
    const std::size_t n = std::size_t(std::min<std::uint64_t>(found->second, size));
    return bool(walkMessages(bytes, n, remember, heapObject));
  }
  if (size >= 6 && std::memcmp(bytes, "OHDR", 4) == 0 && bytes[4] == 2)
  {
    // A version 2 header (IV.A.1.b): signature, version, flags, optional times (16 bytes) and
    // attribute phase change values (4 bytes), then chunk 0's size in 1, 2, 4 or 8 bytes.
    const unsigned flags = bytes[5];
    const std::size_t width = std::size_t(1) << (flags & 0x03);
    const std::size_t at = 6 + ((flags & 0x20) != 0 ? 16 : 0) + ((flags & 0x10) != 0 ? 4 : 0);
    return size < at + width || inFile(addr + at + width, little(bytes + at, int(width)));
  }
  if (size < PrefixBytes || bytes[0] != 1 || bytes[1] != 0)
  {
    return true; // not a version 1 header's first chunk
  }
  const std::uint64_t chunk = little(bytes + 8, 4);
  if (!inFile(addr + PrefixBytes, chunk))
  {
    return false;
  }
  const std::size_t n = std::size_t(std::min<std::uint64_t>(chunk, size - PrefixBytes));
  return bool(walkMessages(bytes + PrefixBytes, n, remember, heapObject));
}

herr_t readChecked(H5FD_t* file, H5FD_mem_t type, hid_t, haddr_t addr, size_t size, void* buffer)
{
  CheckedFile* f = self(file);
  auto* bytes = static_cast<unsigned char*>(buffer);
  if (addr == HADDR_UNDEF || addr > MaxAddress || size > MaxAddress - addr ||
      addr + size > f->EndOfAddresses || !readAt(f->Descriptor, addr, size, bytes))
  {
    return -1;
  }
  if (type == H5FD_MEM_OHDR)
  {
    try
    {
      return checkObjectHeaderRead(*f, addr, bytes, size) ? 0 : -1;
    }
    catch (const std::bad_alloc&)
    {
      return -1;
    }
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

Status checkObjectHeaderMessages(const unsigned char* bytes, std::size_t size)
{
  // No file here: heap references are left unchecked (the driver checks them).
  return walkMessages(
      bytes, size, [](std::uint64_t, std::uint64_t) { return true; },
      [](std::uint64_t, std::uint64_t, std::uint64_t) { return Status::Ok(); });
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
