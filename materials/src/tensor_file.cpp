#include <npf/materials/tensor_file.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace npf {

static_assert(sizeof(float) == 4 && sizeof(double) == 8, "IEEE float sizes expected");

namespace {

constexpr std::size_t kHeaderSize = 18;  // magic 12, version 2, field count 4

bool host_is_little_endian() {
    const std::uint16_t one = 1;
    std::uint8_t first;
    std::memcpy(&first, &one, 1);
    return first == 1;
}

// Reads a little-endian unsigned integer of N bytes; the caller has checked bounds.
template <typename T>
T load_le(const std::uint8_t* p) {
    T v = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) v |= T(T(p[i]) << (8 * i));
    return v;
}


float half_to_float(std::uint16_t h) {
    const std::uint32_t sign = std::uint32_t(h & 0x8000u) << 16;
    const std::uint32_t exponent = (h >> 10) & 0x1fu;
    std::uint32_t mantissa = h & 0x3ffu;
    std::uint32_t bits;
    if (exponent == 0) {
        if (mantissa == 0) {
            bits = sign;
        } else {  // subnormal half: renormalise
            int e = -1;
            do { ++e; mantissa <<= 1; } while ((mantissa & 0x400u) == 0);
            bits = sign | (std::uint32_t(127 - 15 - e) << 23) | ((mantissa & 0x3ffu) << 13);
        }
    } else if (exponent == 31) {
        bits = sign | 0x7f800000u | (mantissa << 13);
    } else {
        bits = sign | ((exponent + 127 - 15) << 23) | (mantissa << 13);
    }
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

// One element of any dtype as double.
double element(const std::uint8_t* p, DType t) {
    switch (t) {
        case DType::U8: return p[0];
        case DType::I8: return std::int8_t(p[0]);
        case DType::U16: return load_le<std::uint16_t>(p);
        case DType::I16: return std::int16_t(load_le<std::uint16_t>(p));
        case DType::U32: return load_le<std::uint32_t>(p);
        case DType::I32: return std::int32_t(load_le<std::uint32_t>(p));
        case DType::U64: return double(load_le<std::uint64_t>(p));
        case DType::I64: return double(std::int64_t(load_le<std::uint64_t>(p)));
        case DType::F16: return half_to_float(load_le<std::uint16_t>(p));
        case DType::F32: {
            std::uint32_t bits = load_le<std::uint32_t>(p);
            float f;
            std::memcpy(&f, &bits, 4);
            return f;
        }
        case DType::F64: {
            std::uint64_t bits = load_le<std::uint64_t>(p);
            double d;
            std::memcpy(&d, &bits, 8);
            return d;
        }
        case DType::Invalid: break;
    }
    return 0.0;
}

std::uint64_t align8(std::uint64_t v) { return (v + 7) & ~std::uint64_t(7); }

}  // namespace

std::size_t dtype_size(DType t) {
    switch (t) {
        case DType::U8: case DType::I8: return 1;
        case DType::U16: case DType::I16: case DType::F16: return 2;
        case DType::U32: case DType::I32: case DType::F32: return 4;
        case DType::U64: case DType::I64: case DType::F64: return 8;
        case DType::Invalid: break;
    }
    return 0;
}

const char* dtype_name(DType t) {
    static const char* names[] = {"invalid", "u8", "i8", "u16", "i16", "u32",
                                  "i32", "u64", "i64", "f16", "f32", "f64"};
    auto i = std::size_t(t);
    return i < sizeof(names) / sizeof(names[0]) ? names[i] : "invalid";
}

std::string TensorField::shape_string() const {
    // Bounded: an error line names at most eight extents, whatever rank a file claims.
    constexpr std::size_t kShown = 8;
    std::ostringstream os;
    os << '[';
    for (std::size_t i = 0; i < shape.size() && i < kShown; ++i) os << (i ? ", " : "") << shape[i];
    if (shape.size() > kShown) os << ", ... (" << shape.size() << " dimensions)";
    os << ']';
    return os.str();
}

constexpr char TensorFile::kMagic[12];

bool TensorFile::has_magic(const void* data, std::size_t size) {
    return size >= sizeof(kMagic) && std::memcmp(data, kMagic, sizeof(kMagic)) == 0;
}

namespace {

// A read-only mapping of a whole file, unmapped with its last owner.
struct Mapping {
    void* address = MAP_FAILED;
    std::size_t length = 0;
    ~Mapping() {
        if (address != MAP_FAILED) ::munmap(address, length);
    }
};

}  // namespace

TensorFile TensorFile::read(const std::string& path) {
    require_regular_file(path);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const std::string why = std::strerror(errno);
        ::close(fd);
        throw Error(path, "cannot read its size: " + why);
    }
    const std::uint64_t size = std::uint64_t(st.st_size);
    if (size == 0) {
        ::close(fd);
        throw Error(path, "empty file");
    }
    if (size > std::uint64_t(std::numeric_limits<std::size_t>::max())) {
        ::close(fd);
        throw Error(path, "larger than this machine can address");
    }
    // Mapped, not read: pages are touched only where fields are converted, so a file's claimed
    // size costs neither memory nor time (a sparse file of 30 GB opens as fast as a small one).
    auto mapping = std::make_shared<Mapping>();
    mapping->length = std::size_t(size);
    mapping->address = ::mmap(nullptr, mapping->length, PROT_READ, MAP_PRIVATE, fd, 0);
    const int map_errno = errno;
    ::close(fd);
    if (mapping->address == MAP_FAILED) throw Error(path, std::string("cannot map the file: ") + std::strerror(map_errno));
    const auto* data = static_cast<const std::uint8_t*>(mapping->address);
    return parse_bytes(std::shared_ptr<const void>(mapping, mapping->address), data, size, path);
}

TensorFile TensorFile::parse(std::vector<std::uint8_t> bytes, const std::string& source) {
    auto owned = std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes));
    return parse_bytes(std::shared_ptr<const void>(owned, owned->data()), owned->data(), owned->size(), source);
}

TensorFile TensorFile::parse_bytes(std::shared_ptr<const void> storage, const std::uint8_t* data, std::uint64_t size,
                                   const std::string& source) {
    if (size == 0) throw Error(source, "empty file");
    if (size < sizeof(kMagic) || !has_magic(data, size)) {
        throw Error(source, "not a tensor_file (wrong magic: expected \"tensor_file\\0\")");
    }
    if (size < kHeaderSize) {
        throw Error(source, "truncated header (" + std::to_string(size) + " bytes, need " +
                                std::to_string(kHeaderSize) + ")");
    }
    const int major = data[12], minor = data[13];
    if (major != 1 || minor != 0) {
        throw Error(source, "unsupported tensor_file version " + std::to_string(major) + "." +
                                std::to_string(minor) + " (expected 1.0)");
    }
    const std::uint32_t field_count = load_le<std::uint32_t>(data + 14);
    // Each descriptor takes at least 13 bytes: a count the file cannot hold is hostile.
    if (field_count > (size - kHeaderSize) / 13) {
        throw Error(source, "declares " + std::to_string(field_count) +
                                " fields, more than its size can hold (truncated or corrupt)");
    }

    TensorFile file;
    file.m_source = source;
    std::uint64_t pos = kHeaderSize;
    auto need = [&](std::uint64_t n, std::uint32_t index) {
        if (n > size - pos) {
            throw Error(source, "truncated field descriptor #" + std::to_string(index) +
                                    " at byte " + std::to_string(pos));
        }
    };
    for (std::uint32_t i = 0; i < field_count; ++i) {
        TensorField f;
        need(2, i);
        const std::uint16_t name_length = load_le<std::uint16_t>(data + pos);
        pos += 2;
        need(name_length, i);
        f.name.assign(reinterpret_cast<const char*>(data + pos), name_length);
        pos += name_length;
        need(2 + 1 + 8, i);
        const std::uint16_t rank = load_le<std::uint16_t>(data + pos);
        const std::uint8_t code = data[pos + 2];
        f.offset = load_le<std::uint64_t>(data + pos + 3);
        pos += 11;
        if (code == 0 || code > 11) {
            throw Error(source, "field '" + f.name + "' has invalid dtype code " + std::to_string(code));
        }
        f.dtype = DType(code);
        if (rank > kMaxRank) {
            throw Error(source, "field '" + f.name + "' has " + std::to_string(rank) + " dimensions, more than " +
                                    std::to_string(kMaxRank) + " (corrupt)");
        }
        need(std::uint64_t(rank) * 8, i);
        f.count = 1;
        bool overflow = false;
        for (std::uint16_t d = 0; d < rank; ++d) {
            std::uint64_t extent = load_le<std::uint64_t>(data + pos);
            pos += 8;
            f.shape.push_back(extent);
            overflow = overflow || __builtin_mul_overflow(f.count, extent, &f.count);
        }
        std::uint64_t payload_bytes = 0;
        overflow = overflow || __builtin_mul_overflow(f.count, std::uint64_t(dtype_size(f.dtype)), &payload_bytes);
        if (overflow) {
            throw Error(source, "field '" + f.name + "' has a shape " + f.shape_string() +
                                    " whose size overflows");
        }
        if (payload_bytes > kMaxFieldBytes) {
            throw Error(source, "field '" + f.name + "' has a shape " + f.shape_string() + " of " +
                                    std::to_string(payload_bytes) + " bytes, more than the " +
                                    std::to_string(kMaxFieldBytes >> 20) + " MiB a field may hold");
        }
        if (f.offset > size || payload_bytes > size - f.offset) {
            throw Error(source, "field '" + f.name + "' payload (offset " + std::to_string(f.offset) +
                                    ", " + std::to_string(payload_bytes) +
                                    " bytes) extends past the end of the file (" +
                                    std::to_string(size) + " bytes)");
        }
        if (file.find(f.name)) throw Error(source, "duplicate field '" + f.name + "'");
        file.m_fields.push_back(std::move(f));
    }
    file.m_storage = std::move(storage);
    file.m_data = data;
    file.m_size = size;
    return file;
}

const TensorField* TensorFile::find(const std::string& name) const {
    for (const TensorField& f : m_fields) {
        if (f.name == name) return &f;
    }
    return nullptr;
}

const TensorField& TensorFile::require(const std::string& name) const {
    const TensorField* f = find(name);
    if (!f) throw Error(m_source, "missing required field '" + name + "'");
    return *f;
}

std::vector<double> TensorFile::to_double(const TensorField& f) const {
    std::vector<double> out(std::size_t(f.count));
    const std::size_t step = dtype_size(f.dtype);
    const std::uint8_t* p = payload(f);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = element(p + i * step, f.dtype);
    return out;
}

std::vector<float> TensorFile::to_float(const TensorField& f) const {
    std::vector<float> out(std::size_t(f.count));
    const std::uint8_t* p = payload(f);
    if (f.dtype == DType::F32 && host_is_little_endian()) {
        if (!out.empty()) std::memcpy(out.data(), p, out.size() * 4);  // the common case, fast
        return out;
    }
    const std::size_t step = dtype_size(f.dtype);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = float(element(p + i * step, f.dtype));
    return out;
}

std::string TensorFile::to_string(const TensorField& f) const {
    return std::string(reinterpret_cast<const char*>(payload(f)), std::size_t(f.byte_size()));
}

void TensorFile::expect_dtype(const TensorField& f, DType t) const {
    if (f.dtype != t) {
        throw Error(m_source, "field '" + f.name + "' has dtype " + dtype_name(f.dtype) +
                                  ", expected " + dtype_name(t));
    }
}

void TensorFile::expect_rank(const TensorField& f, std::size_t rank) const {
    if (f.shape.size() != rank) {
        throw Error(m_source, "field '" + f.name + "' has shape " + f.shape_string() + ", expected " +
                                  std::to_string(rank) + " dimensions");
    }
}

void TensorFileWriter::add(const std::string& name, DType dtype,
                           const std::vector<std::uint64_t>& shape, const void* data) {
    if (dtype_size(dtype) == 0) throw Error(name, "cannot write a field of invalid dtype");
    if (name.size() > 0xffff || shape.size() > 0xffff) throw Error(name, "field name or rank too long");
    std::uint64_t count = 1;
    for (std::uint64_t e : shape) count *= e;
    Pending p{name, dtype, shape, {}};
    const std::size_t step = dtype_size(dtype);
    p.bytes.resize(std::size_t(count * step));
    const auto* src = static_cast<const std::uint8_t*>(data);
    if (host_is_little_endian() || step == 1) {
        if (!p.bytes.empty()) std::memcpy(p.bytes.data(), src, p.bytes.size());
    } else {
        for (std::size_t i = 0; i < count; ++i)
            for (std::size_t b = 0; b < step; ++b) p.bytes[i * step + b] = src[i * step + step - 1 - b];
    }
    m_fields.push_back(std::move(p));
}

void TensorFileWriter::add_f32(const std::string& name, const std::vector<std::uint64_t>& shape,
                               const std::vector<float>& values) {
    add(name, DType::F32, shape, values.data());
}

void TensorFileWriter::add_u8(const std::string& name, const std::vector<std::uint64_t>& shape,
                              const std::vector<std::uint8_t>& values) {
    add(name, DType::U8, shape, values.data());
}

void TensorFileWriter::add_string(const std::string& name, const std::string& text) {
    add(name, DType::U8, {std::uint64_t(text.size())}, text.data());
}

std::vector<std::uint8_t> TensorFileWriter::serialize() const {
    std::uint64_t descriptors = 0;
    for (const Pending& p : m_fields) descriptors += 13 + p.name.size() + 8 * p.shape.size();
    std::vector<std::uint64_t> offsets;
    std::uint64_t offset = align8(kHeaderSize + descriptors);
    for (const Pending& p : m_fields) {
        offsets.push_back(offset);
        offset = align8(offset + p.bytes.size());
    }
    // One buffer of the final size, filled through a cursor; padding stays zero.
    std::vector<std::uint8_t> out(std::size_t(offset), 0);
    std::size_t pos = 0;
    auto put = [&](const void* src, std::size_t n) {
        if (n) std::memcpy(out.data() + pos, src, n);
        pos += n;
    };
    auto put_le = [&](std::uint64_t v, std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) out[pos++] = std::uint8_t(v >> (8 * i));
    };
    put(TensorFile::kMagic, sizeof(TensorFile::kMagic));
    put_le(1, 1);
    put_le(0, 1);
    put_le(m_fields.size(), 4);
    for (std::size_t i = 0; i < m_fields.size(); ++i) {
        const Pending& p = m_fields[i];
        put_le(p.name.size(), 2);
        put(p.name.data(), p.name.size());
        put_le(p.shape.size(), 2);
        put_le(std::uint64_t(p.dtype), 1);
        put_le(offsets[i], 8);
        for (std::uint64_t e : p.shape) put_le(e, 8);
    }
    for (std::size_t i = 0; i < m_fields.size(); ++i) {
        pos = std::size_t(offsets[i]);
        put(m_fields[i].bytes.data(), m_fields[i].bytes.size());
    }
    return out;
}

void TensorFileWriter::write(const std::string& path) const {
    std::vector<std::uint8_t> bytes = serialize();
    write_file_atomically(path, bytes.data(), bytes.size());
}

}  // namespace npf
