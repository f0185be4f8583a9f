// The "tensor_file" v1.0 container of the RGL material database (docs/rgl-format.md, sec. 1):
// a little-endian header, named fields with a dtype and a shape, payloads at absolute offsets.
//
// TensorFile validates the whole container's structure up front, so that every later access is
// in bounds: a truncated, hostile or inconsistent file is rejected with an npf::Error naming
// the file and the problem, never read past its end. A file is mapped, not read: what it costs
// is what its fields hold, not what its size claims (a sparse 30 GB file costs nothing until a
// field is converted, and no field may claim more than kMaxFieldBytes). TensorFileWriter writes
// files that every reference reader accepts (payloads 8-byte aligned, in descriptor order).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace npf {

enum class DType : std::uint8_t {
    Invalid = 0, U8 = 1, I8 = 2, U16 = 3, I16 = 4, U32 = 5, I32 = 6, U64 = 7, I64 = 8,
    F16 = 9, F32 = 10, F64 = 11
};

std::size_t dtype_size(DType t);       // bytes per element; 0 for Invalid
const char* dtype_name(DType t);       // "u8", "f32", ...

struct TensorField {
    std::string name;
    DType dtype = DType::Invalid;
    std::vector<std::uint64_t> shape;  // outermost axis first
    std::uint64_t offset = 0;          // absolute byte offset of the payload
    std::uint64_t count = 0;           // product of the extents (validated not to overflow)

    std::uint64_t byte_size() const { return count * dtype_size(dtype); }
    std::string shape_string() const;  // "[1, 8, 32, 32]"
};

class TensorFile {
public:
    static constexpr char kMagic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_',
                                        'f', 'i', 'l', 'e', '\0'};
    // The largest payload one field may declare: 1 GiB. The largest measured files of the RGL
    // database are a few hundred MB in all, and every field is converted to floats in memory,
    // so a field above this is a hostile or damaged file, rejected before any allocation.
    static constexpr std::uint64_t kMaxFieldBytes = std::uint64_t(1) << 30;
    // Shapes of more dimensions than this are not RGL's (rank 5 at most) and are rejected.
    static constexpr std::size_t kMaxRank = 16;

    // Throws npf::Error naming `path` for a missing, unreadable or malformed file.
    static TensorFile read(const std::string& path);
    // Parses bytes already in memory; `source` names them in error messages.
    static TensorFile parse(std::vector<std::uint8_t> bytes, const std::string& source);
    // True if the bytes start with the tensor_file magic (for format sniffing).
    static bool has_magic(const void* data, std::size_t size);

    const std::string& source() const { return m_source; }
    std::uint64_t size_bytes() const { return m_size; }
    const std::vector<TensorField>& fields() const { return m_fields; }

    const TensorField* find(const std::string& name) const;
    const TensorField& require(const std::string& name) const;  // "missing required field"

    // Converts any numeric dtype (f16 included) to float / double, C order.
    std::vector<float> to_float(const TensorField& f) const;
    std::vector<double> to_double(const TensorField& f) const;
    // The payload bytes as stored (little-endian).
    const std::uint8_t* payload(const TensorField& f) const { return m_data + f.offset; }
    // A u8 field as text (descriptions).
    std::string to_string(const TensorField& f) const;

    // Shape checks that throw npf::Error naming the file and the field.
    void expect_dtype(const TensorField& f, DType t) const;
    void expect_rank(const TensorField& f, std::size_t rank) const;

private:
    // Validates the structure of `size` bytes at `data` (kept alive by `storage`).
    static TensorFile parse_bytes(std::shared_ptr<const void> storage, const std::uint8_t* data, std::uint64_t size,
                                  const std::string& source);

    std::string m_source;
    std::shared_ptr<const void> m_storage;  // the mapping or the parsed vector; copies share it
    const std::uint8_t* m_data = nullptr;
    std::uint64_t m_size = 0;
    std::vector<TensorField> m_fields;
};

class TensorFileWriter {
public:
    // `data` holds shape-product elements of `dtype` in host order; copied immediately.
    void add(const std::string& name, DType dtype, const std::vector<std::uint64_t>& shape,
             const void* data);
    void add_f32(const std::string& name, const std::vector<std::uint64_t>& shape,
                 const std::vector<float>& values);
    void add_u8(const std::string& name, const std::vector<std::uint64_t>& shape,
                const std::vector<std::uint8_t>& values);
    void add_string(const std::string& name, const std::string& text);  // u8 [n]

    std::vector<std::uint8_t> serialize() const;
    // Atomic: temporary file, then rename. Throws npf::Error naming `path`.
    void write(const std::string& path) const;

private:
    struct Pending {
        std::string name;
        DType dtype;
        std::vector<std::uint64_t> shape;
        std::vector<std::uint8_t> bytes;  // little-endian
    };
    std::vector<Pending> m_fields;
};

}  // namespace npf
