// Neural BRDF reader and evaluator. The weights are read once with the HDF5 C API; evaluation is
// a float forward pass over arrays on the stack, so eval never touches HDF5 and never allocates.
#include <npf/materials/nbrdf_brdf.h>

#include <npf/core/number_text.h>
#include <npf/core/cosine_sampling.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>
#include <npf/core/text.h>

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <mutex>

namespace npf {

namespace {

constexpr int kLayerCount = 3;
// The HDF5 format signature (at offset 0 unless the file has a user block).
constexpr std::uint8_t kHdf5Signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

// Debian's HDF5 is built without thread safety: one loader at a time.
std::mutex& hdf5_mutex() {
    static std::mutex m;
    return m;
}

// HDF5 prints its whole error stack to stderr by default; a bad file must give exactly one line
// (our npf::Error), so printing is off while we read, and restored afterwards.
class QuietHdf5Errors {
public:
    QuietHdf5Errors() {
        H5Eget_auto2(H5E_DEFAULT, &m_func, &m_data);
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
    ~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, m_func, m_data); }
    QuietHdf5Errors(const QuietHdf5Errors&) = delete;
    QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;

private:
    H5E_auto2_t m_func = nullptr;
    void* m_data = nullptr;
};

// Owns one HDF5 identifier and closes it with the matching function.
class Handle {
public:
    using Closer = herr_t (*)(hid_t);
    Handle(hid_t id, Closer close) : m_id(id), m_close(close) {}
    ~Handle() {
        if (m_id >= 0) m_close(m_id);
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    hid_t get() const { return m_id; }
    bool valid() const { return m_id >= 0; }

private:
    hid_t m_id;
    Closer m_close;
};

std::string dataset_path(int layer, const char* weight) {
    const std::string name = "dense_" + std::to_string(layer);
    return name + "/" + name + "/" + weight + ":0";
}

std::string shape_text(const std::vector<hsize_t>& dims) {
    if (dims.empty()) return "a scalar";
    std::string text;
    for (std::size_t i = 0; i < dims.size(); ++i)
        text += (i ? " x " : "") + std::to_string(static_cast<unsigned long long>(dims[i]));
    return text;
}

// What a file says about where data lie (a link target, an external file name) is shown in
// messages cut to this length, so that a file cannot fill the message.
constexpr std::size_t kMaxQuoted = 200;

std::string quoted(std::string text) {
    if (text.size() > kMaxQuoted) text = text.substr(0, kMaxQuoted) + "...";
    return text;
}

// The text of a C buffer that HDF5 filled, up to its terminator or its end.
std::string buffer_text(const std::vector<char>& buffer) {
    return std::string(buffer.data(), strnlen(buffer.data(), buffer.size()));
}

// Refuses the traversal of any external link HDF5 might meet while resolving a name, in case
// one escapes the checks of each link below (a second line of defence; they come first).
herr_t refuse_external_link(const char*, const char*, const char*, const char*, unsigned*, hid_t, void*) {
    return -1;
}

// Number of hard links to an object and its type. H5Oget_info's signature changed in 1.12.
bool object_links(hid_t location, const char* name, hid_t lapl, unsigned& links, H5O_type_t& type) {
#if H5_VERSION_GE(1, 12, 0)
    H5O_info2_t info;
    if (H5Oget_info_by_name3(location, name, &info, H5O_INFO_BASIC, lapl) < 0) return false;
#else
    H5O_info_t info;
    if (H5Oget_info_by_name2(location, name, &info, H5O_INFO_BASIC, lapl) < 0) return false;
#endif
    links = info.rc;
    type = info.type;
    return true;
}

const char* builtin_filter_name(H5Z_filter_t id) {
    switch (id) {
        case H5Z_FILTER_DEFLATE: return "deflate";
        case H5Z_FILTER_SHUFFLE: return "shuffle";
        case H5Z_FILTER_FLETCHER32: return "fletcher32";
        case H5Z_FILTER_SZIP: return "szip";
        case H5Z_FILTER_NBIT: return "nbit";
        case H5Z_FILTER_SCALEOFFSET: return "scaleoffset";
        default: return nullptr;
    }
}

// Reads the network's datasets from one HDF5 file and from nothing else. HDF5 can make a file
// read other things: external links (an object in another file), external storage (a dataset's
// bytes in any file, a FIFO or a device included), virtual datasets (mapped from other files'
// datasets), filters loaded from plugins (shared libraries). Each is refused before any data are
// read, with soft links too (they can lead through external links and loops, and a network
// needs none) and objects linked more than once (a loop, or one dataset posing as two).
class OwnFileReader {
public:
    OwnFileReader(hid_t file, const std::string& path, std::uint64_t file_bytes)
        : m_file(file), m_path(path), m_lapl(H5Pcreate(H5P_LINK_ACCESS), H5Pclose),
          m_dapl(H5Pcreate(H5P_DATASET_ACCESS), H5Pclose) {
        if (!m_lapl.valid() || !m_dapl.valid() ||
            H5Pset_elink_cb(m_lapl.get(), refuse_external_link, nullptr) < 0 ||
            H5Pset_elink_cb(m_dapl.get(), refuse_external_link, nullptr) < 0)
            throw Error(m_path, "cannot set up the HDF5 library to read the file");
        Handle fcpl(H5Fget_create_plist(m_file), H5Pclose);
        hsize_t user_block = 0;
        if (!fcpl.valid() || H5Pget_userblock(fcpl.get(), &user_block) < 0 || user_block > file_bytes)
            throw Error(m_path, "cannot read the HDF5 file's superblock (truncated or damaged)");
        m_data_bytes = file_bytes - user_block;
        unsigned links = 0;
        H5O_type_t type = H5O_TYPE_UNKNOWN;
        if (!object_links(m_file, ".", m_lapl.get(), links, type))
            throw Error(m_path, "cannot read the HDF5 file's root group (truncated or damaged)");
        if (links != 1) throw Error(m_path, several_links("the root group", links));
    }

    // Whether the object `name` ("a/b/c") exists, every link on the way checked (see above).
    bool exists(const std::string& name) const {
        for (std::size_t end = name.find('/');; end = name.find('/', end + 1)) {
            const std::string prefix = name.substr(0, end);
            if (!check_link(prefix, end == std::string::npos)) return false;
            if (end == std::string::npos) return true;
        }
    }

    // Reads one floating-point dataset as float, with its shape. Throws npf::Error.
    std::vector<float> read_floats(const std::string& name, std::vector<hsize_t>& dims) const {
        if (!exists(name)) throw Error(m_path, "missing dataset " + name);
        Handle dataset(H5Dopen2(m_file, name.c_str(), m_dapl.get()), H5Dclose);
        if (!dataset.valid()) throw Error(m_path, name + " is not a readable dataset");
        Handle dcpl(H5Dget_create_plist(dataset.get()), H5Pclose);
        if (!dcpl.valid()) throw Error(m_path, "cannot read how dataset " + name + " is stored (file damaged)");
        const H5D_layout_t layout = check_stored_inside(dcpl.get(), name);

        Handle type(H5Dget_type(dataset.get()), H5Tclose);
        if (!type.valid() || H5Tget_class(type.get()) != H5T_FLOAT)
            throw Error(m_path, "dataset " + name + " does not hold floating-point numbers");
        // IEEE single or double precision: HDF5 can describe other layouts of bits, which no
        // Keras file holds and whose conversion is little-exercised code.
        const bool ieee = H5Tequal(type.get(), H5T_IEEE_F32LE) > 0 || H5Tequal(type.get(), H5T_IEEE_F32BE) > 0 ||
                          H5Tequal(type.get(), H5T_IEEE_F64LE) > 0 || H5Tequal(type.get(), H5T_IEEE_F64BE) > 0;
        if (!ieee)
            throw Error(m_path, "dataset " + name + " holds floating-point numbers of " +
                                    std::to_string(H5Tget_size(type.get())) +
                                    " bytes that are not IEEE single or double precision");
        const hsize_t value_bytes = H5Tget_size(type.get());

        Handle space(H5Dget_space(dataset.get()), H5Sclose);
        const int rank = space.valid() && H5Sget_simple_extent_type(space.get()) != H5S_NULL
                             ? H5Sget_simple_extent_ndims(space.get())
                             : -1;
        if (rank < 0 || rank > 2) throw Error(m_path, "dataset " + name + " has an unusable shape");
        dims.assign(static_cast<std::size_t>(rank), 0);
        if (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0)
            throw Error(m_path, "dataset " + name + " has an unusable shape");
        // Shapes are checked by the caller; this only bounds the allocation before reading, by
        // the largest layer accepted (kMaxHiddenUnits squared).
        hsize_t count = 1;
        for (hsize_t d : dims) {
            if (d > kMaxValues || count * d > kMaxValues)
                throw Error(m_path, "dataset " + name + " is too large (" + shape_text(dims) + ")");
            count *= d;
        }
        if (count > 0) check_storage_size(dataset.get(), dcpl.get(), layout, name, dims, count * value_bytes, value_bytes);

        std::vector<float> values(static_cast<std::size_t>(count));
        if (count > 0 && H5Dread(dataset.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                                 values.data()) < 0)
            throw Error(m_path, "cannot read dataset " + name + " (file truncated or damaged)");
        return values;
    }

private:
    static constexpr hsize_t kMaxValues = hsize_t(NbrdfBrdf::kMaxHiddenUnits) * NbrdfBrdf::kMaxHiddenUnits;

    // Checks the link `prefix` names (its parents checked already); false when it is absent.
    bool check_link(const std::string& prefix, bool last) const {
        // Negative when a parent is no group: absent too, as the name cannot be resolved.
        if (H5Lexists(m_file, prefix.c_str(), m_lapl.get()) <= 0) return false;
        H5L_info_t link;
        if (H5Lget_info(m_file, prefix.c_str(), &link, m_lapl.get()) < 0)
            throw Error(m_path, "cannot read the link " + prefix + " (file damaged)");
        if (link.type == H5L_TYPE_SOFT)
            throw Error(m_path, prefix + " is a soft link (to " + quoted(link_value(prefix, link.u.val_size, false)) +
                                    "): a material is read through its own hard links alone");
        if (link.type == H5L_TYPE_EXTERNAL)
            throw Error(m_path, prefix + " is an external link (to " + quoted(link_value(prefix, link.u.val_size, true)) +
                                    "): a material is read from its own file alone");
        if (link.type != H5L_TYPE_HARD)
            throw Error(m_path, prefix + " is a user-defined link (type " + std::to_string(int(link.type)) +
                                    "): a material is read through its own hard links alone");
        unsigned links = 0;
        H5O_type_t type = H5O_TYPE_UNKNOWN;
        if (!object_links(m_file, prefix.c_str(), m_lapl.get(), links, type))
            throw Error(m_path, "cannot read the object " + prefix + " (file truncated or damaged)");
        if (links != 1) throw Error(m_path, several_links(prefix, links));
        return last || type == H5O_TYPE_GROUP;
    }

    static std::string several_links(const std::string& what, unsigned links) {
        return what + " has " + std::to_string(links) +
               " hard links to it (a link loop, or one object under several names): each object of a material has one path";
    }

    // A soft link's target path, or an external link's "file:/object".
    std::string link_value(const std::string& name, std::size_t size, bool external) const {
        std::vector<char> value(std::min<std::size_t>(size, 4 * kMaxQuoted) + 1, '\0');
        if (H5Lget_val(m_file, name.c_str(), value.data(), value.size() - 1, m_lapl.get()) < 0) return "?";
        if (!external) return buffer_text(value);
        // An external link's value: a flags byte, then the file name and the object path, each
        // NUL-terminated (parsed here: H5Lunpack_elink_val trusts the terminators to be there).
        const std::size_t used = value.size() - 1;
        if (used < 2) return "?";
        const char* file = value.data() + 1;
        const std::size_t file_length = strnlen(file, used - 1);
        const std::size_t object_at = 1 + file_length + 1;
        std::string object;
        if (object_at < used) object.assign(value.data() + object_at, strnlen(value.data() + object_at, used - object_at));
        return std::string(file, file_length) + ":" + object;
    }

    // Refuses a dataset whose data are not stored inside the file, or need a filter HDF5 does
    // not build in (it would look for a plugin). Returns the layout.
    H5D_layout_t check_stored_inside(hid_t dcpl, const std::string& name) const {
        const H5D_layout_t layout = H5Pget_layout(dcpl);
        if (layout == H5D_VIRTUAL) {
            std::vector<char> file(kMaxQuoted + 1, '\0'), source(kMaxQuoted + 1, '\0');
            std::size_t mappings = 0;
            std::string from = "?";
            if (H5Pget_virtual_count(dcpl, &mappings) >= 0 && mappings > 0 &&
                H5Pget_virtual_filename(dcpl, 0, file.data(), file.size() - 1) >= 0 &&
                H5Pget_virtual_dsetname(dcpl, 0, source.data(), source.size() - 1) >= 0)
                from = buffer_text(file) + ":" + buffer_text(source);
            throw Error(m_path, "dataset " + name + " is a virtual dataset (mapped from " + quoted(from) +
                                    "): a material is read from its own file alone");
        }
        const int externals = H5Pget_external_count(dcpl);
        if (externals < 0) throw Error(m_path, "cannot read how dataset " + name + " is stored (file damaged)");
        if (externals > 0) {
            std::vector<char> file(kMaxQuoted + 1, '\0');
            off_t offset = 0;
            hsize_t bytes = 0;
            const std::string where = H5Pget_external(dcpl, 0, file.size() - 1, file.data(), &offset, &bytes) >= 0
                                          ? buffer_text(file)
                                          : "?";
            throw Error(m_path, "dataset " + name + " uses external storage (file " + quoted(where) +
                                    "): a material is read from its own file alone");
        }
        if (layout != H5D_CONTIGUOUS && layout != H5D_COMPACT && layout != H5D_CHUNKED)
            throw Error(m_path, "dataset " + name + " has an unknown storage layout (file damaged)");
        const int filters = H5Pget_nfilters(dcpl);
        if (filters < 0) throw Error(m_path, "cannot read the filters of dataset " + name + " (file damaged)");
        for (int i = 0; i < filters; ++i) {
            unsigned flags = 0, config = 0;
            std::size_t parameters = 0;
            std::vector<char> file_name(64 + 1, '\0');
            const H5Z_filter_t id = H5Pget_filter2(dcpl, unsigned(i), &flags, &parameters, nullptr,
                                                   file_name.size() - 1, file_name.data(), &config);
            const char* builtin = builtin_filter_name(id);
            if (builtin == nullptr)
                throw Error(m_path, "dataset " + name + " needs filter " + std::to_string(id) + " (" +
                                        quoted(buffer_text(file_name)) +
                                        "), which is not built into HDF5: plugins are never loaded for a material");
            if (H5Zfilter_avail(id) <= 0)
                throw Error(m_path, "dataset " + name + " needs filter " + std::to_string(id) + " (" + builtin +
                                        "), which this HDF5 library is built without");
        }
        return layout;
    }

    // Checks, before reading, that the file stores exactly the bytes the dataset claims, inside
    // the file: nothing is filled in from a fill value, and no read relies on HDF5 1.10 to check
    // a size (its fill, compact and chunk paths trust the sizes a file gives: a chunk recorded as
    // 45 bytes was read as its 48 and overran the buffer). A compressed chunk may be no larger
    // than its values (deflate's output grows until the stream ends: a small chunk could claim
    // gigabytes).
    void check_storage_size(hid_t dataset, hid_t dcpl, H5D_layout_t layout, const std::string& name,
                            const std::vector<hsize_t>& dims, hsize_t raw_bytes, hsize_t value_bytes) const {
        const std::string damaged = "dataset " + name + " ";
        const auto check_inside = [&](haddr_t address, hsize_t bytes) {
            if (address == HADDR_UNDEF || address > m_data_bytes || bytes > m_data_bytes - address)
                throw Error(m_path, damaged + "lies beyond the end of the file (truncated or damaged)");
        };
        if (layout != H5D_CHUNKED) {
            H5D_space_status_t status = H5D_SPACE_STATUS_ERROR;
            if (H5Dget_space_status(dataset, &status) < 0 || status != H5D_SPACE_STATUS_ALLOCATED)
                throw Error(m_path, damaged + "holds no stored values (never written, or file damaged)");
            const hsize_t stored = H5Dget_storage_size(dataset);
            if (stored != raw_bytes)
                throw Error(m_path, damaged + "stores " + std::to_string(stored) + " bytes for " +
                                        std::to_string(raw_bytes) + " bytes of values (file damaged)");
            if (layout == H5D_CONTIGUOUS) check_inside(H5Dget_offset(dataset), stored);  // compact: in its header
            return;
        }
        const int rank = int(dims.size());
        std::vector<hsize_t> chunk(dims.size(), 0);
        if (rank == 0 || H5Pget_chunk(dcpl, rank, chunk.data()) != rank)
            throw Error(m_path, damaged + "has unreadable chunk dimensions (file damaged)");
        hsize_t chunk_values = 1;
        for (hsize_t c : chunk) {
            if (c == 0 || c > kMaxValues || chunk_values * c > kMaxValues)
                throw Error(m_path, damaged + "has chunks of " + shape_text(chunk) + " values, more than a layer holds");
            chunk_values *= c;
        }
        const hsize_t chunk_bytes = chunk_values * value_bytes;
        const bool filtered = H5Pget_nfilters(dcpl) > 0;
        // Deflate's worst expansion of incompressible data is well under this; fletcher32 adds 4.
        const hsize_t most_stored = filtered ? chunk_bytes + chunk_bytes / 256 + 64 : chunk_bytes;
        // Every chunk of the grid, row-major: at most kMaxValues of them, one index look-up each.
        // The size is the index's record (H5Dget_chunk_storage_size gives the nominal size of an
        // unfiltered chunk, whatever the file records).
        std::vector<hsize_t> offset(dims.size(), 0);
        for (;;) {
            unsigned skipped_filters = 0;
            haddr_t address = HADDR_UNDEF;
            hsize_t stored = 0;
            if (H5Dget_chunk_info_by_coord(dataset, offset.data(), &skipped_filters, &address, &stored) < 0 ||
                address == HADDR_UNDEF || stored == 0)
                throw Error(m_path, damaged + "lacks a stored chunk (never written, or file damaged)");
            if (stored > most_stored || (!filtered && stored != chunk_bytes))
                throw Error(m_path, damaged + "stores " + std::to_string(stored) + " bytes for a chunk of " +
                                        std::to_string(chunk_bytes) + " bytes of values (file damaged)");
            check_inside(address, stored);
            int axis = rank - 1;
            for (; axis >= 0; --axis) {
                offset[axis] += chunk[axis];
                if (offset[axis] < dims[axis]) break;
                offset[axis] = 0;
            }
            if (axis < 0) return;
        }
    }

    hid_t m_file;
    std::string m_path;
    hsize_t m_data_bytes = 0;  // the file's bytes after its user block: HDF5's addresses start there
    Handle m_lapl, m_dapl;
};

bool all_finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Layer widths are padded with zero weights to a multiple of this many lanes, so that the inner
// loops have trip counts the compiler vectorises without remainder loops.
constexpr int kLanes = 8;

int padded(int units) { return (units + kLanes - 1) / kLanes * kLanes; }

// y = relu?(x W + b) for one dense layer of `Stride` (padded) units; W row-major, inputs x
// Stride, padding columns zero. With the width known at compile time all the sums stay in
// registers and the inputs' additions overlap; loops over a run-time width were 1.5 to 2x slower.
template <int Stride>
void dense_fixed(const float* x, int inputs, const float* kernel, const float* bias, bool relu,
                 float* y) {
    float sum[Stride];
    for (int j = 0; j < Stride; ++j) sum[j] = bias[j];
    for (int i = 0; i < inputs; ++i) {
        const float xi = x[i];
        const float* row = kernel + static_cast<std::size_t>(i) * Stride;
        for (int j = 0; j < Stride; ++j) sum[j] += xi * row[j];
    }
    for (int j = 0; j < Stride; ++j) y[j] = relu ? std::max(sum[j], 0.f) : sum[j];
}

// Any width: kLanes outputs at a time.
void dense_blocks(const float* x, int inputs, const float* kernel, const float* bias, int stride,
                  bool relu, float* y) {
    for (int j0 = 0; j0 < stride; j0 += kLanes) {
        float sum[kLanes];
        for (int j = 0; j < kLanes; ++j) sum[j] = bias[j0 + j];
        for (int i = 0; i < inputs; ++i) {
            const float xi = x[i];
            const float* row = kernel + static_cast<std::size_t>(i) * stride + j0;
            for (int j = 0; j < kLanes; ++j) sum[j] += xi * row[j];
        }
        for (int j = 0; j < kLanes; ++j) y[j0 + j] = relu ? std::max(sum[j], 0.f) : sum[j];
    }
}

void dense(const float* x, int inputs, const float* kernel, const float* bias, int stride,
           bool relu, float* y) {
    switch (stride) {
        case 8: return dense_fixed<8>(x, inputs, kernel, bias, relu, y);    // the RGB output layer
        case 24: return dense_fixed<24>(x, inputs, kernel, bias, relu, y);  // the published 21 units
        case 32: return dense_fixed<32>(x, inputs, kernel, bias, relu, y);
        default: return dense_blocks(x, inputs, kernel, bias, stride, relu, y);
    }
}


// ---- The value bound ---------------------------------------------------------------------
// An upper bound of f_r cos(theta_i) cos(theta_o) over every direction pair (brdf.h), by
// interval arithmetic through the network. A pair enters as (sin theta_h, 0, cos theta_h, d),
// d the unit difference vector, whose d.z = cos theta_d is >= 0 (wo . h >= 0); so the input
// domain is the box theta_h, theta_d in [0, pi/2], phi_d in [0, 2 pi], with
// d = (sin theta_d cos phi_d, sin theta_d sin phi_d, cos theta_d). Rotating d back gives
// cos theta_o = d.z cos theta_h - d.x sin theta_h, and wi, the mirror of wo about h,
// cos theta_i = d.z cos theta_h + d.x sin theta_h: their product is (d.z cos theta_h)^2 -
// (d.x sin theta_h)^2. Over the whole box the bound is loose (a published network's is up to
// 1e25); split into boxes, each bounded separately, it comes within a small factor of the
// network's true maximum.

struct LayerView {
    const float* kernel;  // inputs x stride, row-major
    const float* bias;
    int inputs, units, stride;
};

struct Interval {
    double lo, hi;
};

constexpr double kPiDouble = 3.14159265358979323846;  // npf::kPi is a float

// sin over [a, b], b - a <= 2 pi, both in [0, 3 pi].
Interval sin_over(double a, double b) {
    Interval r{std::min(std::sin(a), std::sin(b)), std::max(std::sin(a), std::sin(b))};
    for (double peak = kPiDouble / 2; peak <= b; peak += 2 * kPiDouble)
        if (peak >= a) r.hi = 1;
    for (double trough = 3 * kPiDouble / 2; trough <= b; trough += 2 * kPiDouble)
        if (trough >= a) r.lo = -1;
    return r;
}

Interval cos_over(double a, double b) { return sin_over(a + kPiDouble / 2, b + kPiDouble / 2); }

Interval times(const Interval& x, const Interval& y) {
    const double p[4] = {x.lo * y.lo, x.lo * y.hi, x.hi * y.lo, x.hi * y.hi};
    return {*std::min_element(p, p + 4), *std::max_element(p, p + 4)};
}

// The network's inputs are computed in float from directions that are unit vectors to float
// precision: each lies within this of its value for the exact angles.
constexpr double kInputSlack = 1e-5;
// Largest |activation| accepted: sums of up to 257 terms each below it stay far from float's
// 3.4e38, so the float forward pass cannot overflow on the way.
constexpr double kMaxActivation = 1e30;
// Largest output x accepted: expm1f(x) below float's largest value.
constexpr double kMaxOutput = 88.0;
// Bounding stops at this many boxes, or at this much work (interval multiply-adds), or when the
// bound is within a factor of 2 of a value the network reaches; it is sound whenever it stops.
constexpr int kMaxBoundBoxes = 4096;
constexpr double kMaxBoundWork = 1 << 23;

struct AngleBox {
    double lo[3], hi[3];  // theta_h, theta_d, phi_d
};

struct BoxBound {
    // Whether a pair with both directions above the horizon may lie in the box: eval_cos
    // evaluates the network for those alone (at their exact angles, inputs rounded).
    bool reachable = false;
    double value = 0;       // bound of |f_r| cos(theta_i) cos(theta_o) over the box
    double activation = 0;  // bound of |a| over every unit, hidden and output, before ReLU
    double output = 0;      // bound of the outputs x (before exp(x) - 1)
    bool overflows() const { return reachable && (!(activation <= kMaxActivation) || !(output <= kMaxOutput)); }
};

BoxBound bound_over(const LayerView (&layers)[3], const AngleBox& box) {
    const Interval hx = sin_over(box.lo[0], box.hi[0]), hz = cos_over(box.lo[0], box.hi[0]);
    const Interval sin_d = sin_over(box.lo[1], box.hi[1]), dz = cos_over(box.lo[1], box.hi[1]);
    const Interval dx = times(sin_d, cos_over(box.lo[2], box.hi[2]));
    const Interval dy = times(sin_d, sin_over(box.lo[2], box.hi[2]));

    Interval a[NbrdfBrdf::kMaxHiddenUnits], b[NbrdfBrdf::kMaxHiddenUnits];
    double magnitude[NbrdfBrdf::kMaxHiddenUnits];
    const Interval input[NbrdfBrdf::kInputs] = {hx, {0, 0}, hz, dx, dy, dz};
    for (int i = 0; i < NbrdfBrdf::kInputs; ++i) a[i] = {input[i].lo - kInputSlack, input[i].hi + kInputSlack};
    Interval* x = a;
    Interval* y = b;
    BoxBound r;
    for (int k = 0; k < kLayerCount; ++k) {
        const LayerView& l = layers[k];
        for (int j = 0; j < l.units; ++j) {
            y[j] = {double(l.bias[j]), double(l.bias[j])};
            magnitude[j] = std::fabs(double(l.bias[j]));
        }
        for (int i = 0; i < l.inputs; ++i) {
            const Interval xi = x[i];
            const double size = std::max(std::fabs(xi.lo), std::fabs(xi.hi));
            const float* row = l.kernel + static_cast<std::size_t>(i) * l.stride;
            for (int j = 0; j < l.units; ++j) {
                const double w = row[j];
                y[j].lo += w * (w >= 0 ? xi.lo : xi.hi);
                y[j].hi += w * (w >= 0 ? xi.hi : xi.lo);
                magnitude[j] += std::fabs(w) * size;
            }
        }
        const bool last = k + 1 == kLayerCount;
        for (int j = 0; j < l.units; ++j) {
            // The float forward pass rounds each product and partial sum: its result is within
            // (n + 1) 2^-24 of the sum of |terms| of the exact one (n terms and the bias).
            const double rounding = (l.inputs + 2) * std::ldexp(1.0, -23) * magnitude[j];
            y[j].lo -= rounding;
            y[j].hi += rounding;
            const double largest = std::max({magnitude[j] + rounding, std::fabs(y[j].lo), std::fabs(y[j].hi)});
            // NaN (inf - inf on absurd weights) is no bound: infinite.
            r.activation = largest <= std::numeric_limits<double>::max() ? std::max(r.activation, largest)
                                                                          : std::numeric_limits<double>::infinity();
            if (!last) y[j] = {std::max(y[j].lo, 0.0), std::max(y[j].hi, 0.0)};
        }
        std::swap(x, y);
    }

    // cos(theta_i) cos(theta_o) = A^2 - B^2 with A = d.z cos theta_h >= 0 and B = d.x sin theta_h,
    // from the exact angles (the box holds them; only the inputs carry rounding).
    const Interval big_a = times(dz, hz), big_b = times(dx, hx);
    const double b_squared_lo = big_b.lo <= 0 && big_b.hi >= 0 ? 0.0 : std::min(big_b.lo * big_b.lo, big_b.hi * big_b.hi);
    const double cosines = std::min(1.0, std::max(big_a.lo * big_a.lo, big_a.hi * big_a.hi) - b_squared_lo);
    // A box with no pair above the horizon on both sides (cosines <= 0) gives nothing.
    r.reachable = cosines > 0;
    if (!r.reachable) return {};
    r.output = -std::numeric_limits<double>::infinity();
    for (int c = 0; c < NbrdfBrdf::kOutputs; ++c) {
        r.output = std::max(r.output, x[c].hi);
        // exp(x) - 1 >= -1; float's expm1 and the final products round: a margin of 2^-20.
        const double f = std::max(std::expm1(x[c].hi), -std::expm1(x[c].lo));
        r.value = std::max(r.value, f * cosines * (1 + std::ldexp(1.0, -20)));
    }
    if (!(r.value >= 0)) r.value = std::numeric_limits<double>::infinity();
    if (std::isnan(r.output)) r.output = std::numeric_limits<double>::infinity();
    return r;
}

// f_r cos(theta_i) cos(theta_o) at the centre of a box, in double: a value the network reaches
// (up to its float rounding), so the largest seen is a lower bound of the true maximum.
double value_at_centre(const LayerView (&layers)[3], const AngleBox& box) {
    const double theta_h = 0.5 * (box.lo[0] + box.hi[0]), theta_d = 0.5 * (box.lo[1] + box.hi[1]),
                 phi_d = 0.5 * (box.lo[2] + box.hi[2]);
    double x[NbrdfBrdf::kMaxHiddenUnits], y[NbrdfBrdf::kMaxHiddenUnits];
    const double dx = std::sin(theta_d) * std::cos(phi_d), dz = std::cos(theta_d);
    const double dy = std::sin(theta_d) * std::sin(phi_d);
    const double input[NbrdfBrdf::kInputs] = {std::sin(theta_h), 0, std::cos(theta_h), dx, dy, dz};
    std::copy(input, input + NbrdfBrdf::kInputs, x);
    for (int k = 0; k < kLayerCount; ++k) {
        const LayerView& l = layers[k];
        for (int j = 0; j < l.units; ++j) y[j] = l.bias[j];
        for (int i = 0; i < l.inputs; ++i)
            for (int j = 0; j < l.units; ++j) y[j] += x[i] * double(l.kernel[static_cast<std::size_t>(i) * l.stride + j]);
        for (int j = 0; j < l.units; ++j) x[j] = k + 1 < kLayerCount ? std::max(y[j], 0.0) : y[j];
    }
    const double a = dz * std::cos(theta_h), b = dx * std::sin(theta_h);
    const double cosines = std::max(0.0, a * a - b * b);
    double best = 0;
    for (int c = 0; c < NbrdfBrdf::kOutputs; ++c) best = std::max(best, std::expm1(x[c]) * cosines);
    return std::isfinite(best) ? best : 0.0;
}

struct NetworkBound {
    double value = 0, activation = 0, output = 0;
    int boxes = 0;
};

// Branch and bound: the box with the largest bound (or one whose float evaluation could
// overflow) is split in two along its widest angle, until the stopping rule above.
NetworkBound bound_network(const LayerView (&layers)[3]) {
    struct Leaf {
        AngleBox box;
        BoxBound bound;
        double priority() const { return bound.overflows() ? std::numeric_limits<double>::infinity() : bound.value; }
    };
    const auto lower_priority = [](const Leaf& p, const Leaf& q) { return p.priority() < q.priority(); };
    double work_per_box = 0;
    for (const LayerView& l : layers) work_per_box += double(l.inputs) * l.units;
    const int budget = std::max(1, std::min(kMaxBoundBoxes, int(kMaxBoundWork / work_per_box)));

    std::vector<Leaf> leaves;
    leaves.reserve(static_cast<std::size_t>(budget) + 1);
    const AngleBox whole{{0, 0, 0}, {kPiDouble / 2, kPiDouble / 2, 2 * kPiDouble}};
    leaves.push_back({whole, bound_over(layers, whole)});
    double reached = value_at_centre(layers, whole);
    int boxes = 1;
    while (boxes + 2 <= budget) {
        const Leaf& top = leaves.front();
        if (!top.bound.overflows() && top.bound.value <= 2 * reached) break;
        std::pop_heap(leaves.begin(), leaves.end(), lower_priority);
        const AngleBox box = leaves.back().box;
        leaves.pop_back();
        int axis = 0;
        double widest = -1;
        for (int k = 0; k < 3; ++k) {
            // phi_d moves d by sin theta_d per radian, at most: half the weight of the thetas'.
            const double width = (box.hi[k] - box.lo[k]) * (k == 2 ? 0.5 : 1.0);
            if (width > widest) widest = width, axis = k;
        }
        const double middle = 0.5 * (box.lo[axis] + box.hi[axis]);
        AngleBox halves[2] = {box, box};
        halves[0].hi[axis] = middle;
        halves[1].lo[axis] = middle;
        for (const AngleBox& half : halves) {
            leaves.push_back({half, bound_over(layers, half)});
            std::push_heap(leaves.begin(), leaves.end(), lower_priority);
            reached = std::max(reached, value_at_centre(layers, half));
        }
        boxes += 2;
    }
    NetworkBound r;
    r.boxes = boxes;
    r.output = -std::numeric_limits<double>::infinity();
    for (const Leaf& leaf : leaves) {
        if (!leaf.bound.reachable) continue;
        r.value = std::max(r.value, leaf.bound.value);
        r.activation = std::max(r.activation, leaf.bound.activation);
        r.output = std::max(r.output, leaf.bound.output);
    }
    return r;
}

}  // namespace

// ---- Loading -----------------------------------------------------------------------------

bool NbrdfBrdf::has_hdf5_signature(const std::uint8_t* head, std::size_t head_size) {
    return head != nullptr && head_size >= sizeof(kHdf5Signature) &&
           std::memcmp(head, kHdf5Signature, sizeof(kHdf5Signature)) == 0;
}

std::unique_ptr<NbrdfBrdf> NbrdfBrdf::load(const std::string& path) {
    const std::uint64_t file_size = require_regular_file(path, "a Neural BRDF file");
    if (file_size == 0) throw Error(path, "file is empty");

    std::lock_guard<std::mutex> lock(hdf5_mutex());
    // HDF5 closes itself at exit; after some damaged files it cannot (an open that failed half
    // way leaves objects behind) and prints "HDF5: infinite loop closing library" and a list
    // to stderr, after npf's one line. Nothing is written through HDF5, so nothing needs that
    // close. Only possible before HDF5's first call in the process (it fails quietly after).
    static const bool no_close_at_exit = H5dont_atexit() >= 0;
    (void)no_close_at_exit;
    QuietHdf5Errors quiet;
    // A filter HDF5 does not build in is looked for as a plugin, a shared library from
    // HDF5_PLUGIN_PATH: code that a material file would choose. Off for the whole process (npf
    // reads HDF5 nowhere else); datasets that need such a filter are refused by name below.
    H5PLset_loading_state(0);
    if (H5Fis_hdf5(path.c_str()) <= 0) throw Error(path, "not an HDF5 file");
    // The POSIX driver, named rather than taken from the defaults, reads this one file.
    Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (!access.valid() || H5Pset_fapl_sec2(access.get()) < 0)
        throw Error(path, "cannot set up the HDF5 library to read the file");
    Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.get()), H5Fclose);
    if (!file.valid()) throw Error(path, "cannot read the HDF5 file (truncated or damaged)");
    const OwnFileReader reader(file.get(), path, file_size);

    auto brdf = std::unique_ptr<NbrdfBrdf>(new NbrdfBrdf());
    int inputs = kInputs;
    for (int k = 0; k < kLayerCount; ++k) {
        const bool last = k + 1 == kLayerCount;
        const std::string kernel_name = dataset_path(k + 1, "kernel");
        const std::string bias_name = dataset_path(k + 1, "bias");
        std::vector<hsize_t> kernel_dims, bias_dims;
        std::vector<float> kernel = reader.read_floats(kernel_name, kernel_dims);
        std::vector<float> bias = reader.read_floats(bias_name, bias_dims);

        const std::string wanted = std::to_string(inputs) + " x " +
                                   (last ? std::to_string(kOutputs) : std::string("n"));
        const bool kernel_ok = kernel_dims.size() == 2 && kernel_dims[0] == hsize_t(inputs) &&
                               (last ? kernel_dims[1] == hsize_t(kOutputs)
                                     : kernel_dims[1] >= 1 && kernel_dims[1] <= hsize_t(kMaxHiddenUnits));
        if (!kernel_ok)
            throw Error(path, kernel_name + " has shape " + shape_text(kernel_dims) + ", expected " +
                                  wanted + (last ? "" : " with 1 <= n <= " + std::to_string(kMaxHiddenUnits)) +
                                  " (network 6 -> n1 -> n2 -> 3)");
        const int units = static_cast<int>(kernel_dims[1]);
        if (bias_dims.size() != 1 || bias_dims[0] != hsize_t(units))
            throw Error(path, bias_name + " has shape " + shape_text(bias_dims) + ", expected " +
                                  std::to_string(units) + " (the kernel's units)");
        for (const std::vector<float>* values : {&kernel, &bias}) {
            const auto bad = std::find_if(values->begin(), values->end(),
                                          [](float v) { return !std::isfinite(v); });
            if (bad != values->end())
                throw Error(path, "non-finite weight in " +
                                      (values == &kernel ? kernel_name : bias_name) + " at index " +
                                      std::to_string(bad - values->begin()));
        }
        DenseLayer& layer = brdf->m_layers[k];
        layer.inputs = inputs;
        layer.units = units;
        layer.stride = padded(units);
        layer.kernel.assign(static_cast<std::size_t>(inputs) * layer.stride, 0.f);
        for (int i = 0; i < inputs; ++i)
            std::copy_n(kernel.begin() + static_cast<std::ptrdiff_t>(i) * units, units,
                        layer.kernel.begin() + static_cast<std::ptrdiff_t>(i) * layer.stride);
        layer.bias.assign(static_cast<std::size_t>(layer.stride), 0.f);
        std::copy(bias.begin(), bias.end(), layer.bias.begin());
        inputs = units;
    }
    // A deeper network would be evaluated wrongly, not approximately: refuse it.
    const std::string extra = "dense_" + std::to_string(kLayerCount + 1);
    if (reader.exists(extra))
        throw Error(path, "has a layer " + extra + ": expected exactly 3 dense layers (6 -> n1 -> n2 -> 3)");
    // The root's keras_version and backend attributes are not read: Keras writes them as
    // variable-length strings, which HDF5 copies into a buffer of the length the file claims
    // (a 4-byte edit made `npf info` take 4 GB and 16 s; a shorter claim overflows the buffer).

    LayerView layers[kLayerCount];
    for (int k = 0; k < kLayerCount; ++k) {
        const DenseLayer& l = brdf->m_layers[k];
        layers[k] = {l.kernel.data(), l.bias.data(), l.inputs, l.units, l.stride};
    }
    const NetworkBound bound = bound_network(layers);
    check_value_bound(path, bound.value,
                      "exp(output) - 1 by interval arithmetic over " + std::to_string(bound.boxes) +
                          " boxes of direction pairs, x cos(theta_i) cos(theta_o)");
    if (!(bound.activation <= kMaxActivation))
        throw Error(path, "a unit of the network can reach " + number_text(bound.activation) +
                              ", beyond the 1e30 within which its float evaluation cannot overflow: refused as corrupt");
    if (!(bound.output <= kMaxOutput))
        throw Error(path, "the network's output x can reach " + number_text(bound.output) +
                              ", and exp(x) - 1 overflows single precision above 88: refused as corrupt");

    const int n1 = brdf->m_layers[0].units, n2 = brdf->m_layers[1].units;
    const int weights = (kInputs + 1) * n1 + (n1 + 1) * n2 + (n2 + 1) * kOutputs;
    BrdfInfo& info = brdf->m_info;
    info.format = "nbrdf";
    info.path = path;
    // The networks carry no description; the material's name is the file name.
    info.description = std::filesystem::path(path).stem().string();
    info.isotropic = true;
    info.channels = Channels::rgb();
    info.file_bytes = file_size;
    info.value_bound = bound.value;
    info.details = {
        {"network", "6 -> " + std::to_string(n1) + " (ReLU) -> " + std::to_string(n2) +
                        " (ReLU) -> 3 (linear), then exp(x) - 1"},
        {"weights", std::to_string(weights)},
        {"input", "half vector (phi_h = 0) and difference vector of wo"},
        {"output", "f_r in 1/sr, R G B"},
        {"sampling", "cosine-weighted"},
    };
    return brdf;
}

// ---- Evaluation --------------------------------------------------------------------------

void NbrdfBrdf::network_input(const Vec3& wi, const Vec3& wo, float input[kInputs]) {
    const Vec3 h = normalize(wi + wo);
    const float sin_h = std::sqrt(h.x * h.x + h.y * h.y);
    const float cos_h = h.z;
    // Rotating by -phi_h about the normal, then by -theta_h about the bitangent, brings the half
    // vector to the normal; the difference vector is wo in that frame. At the normal phi_h is
    // undefined and taken as 0, as atan2(0, 0) gives in the authors' code.
    const float cos_phi = sin_h > 0.f ? h.x / sin_h : 1.f;
    const float sin_phi = sin_h > 0.f ? h.y / sin_h : 0.f;
    const Vec3 v = normalize(wo);
    const float x1 = v.x * cos_phi + v.y * sin_phi;
    const float y1 = -v.x * sin_phi + v.y * cos_phi;
    const Vec3 d = normalize(Vec3(x1 * cos_h - v.z * sin_h, y1, x1 * sin_h + v.z * cos_h));
    input[0] = sin_h;
    input[1] = 0.f;
    input[2] = cos_h;
    input[3] = d.x;
    input[4] = d.y;
    input[5] = d.z;
}

void NbrdfBrdf::forward(const float input[kInputs], float rgb[kOutputs]) const {
    float hidden1[kMaxHiddenUnits], hidden2[kMaxHiddenUnits], linear[kLanes];
    const DenseLayer& a = m_layers[0];
    const DenseLayer& b = m_layers[1];
    const DenseLayer& c = m_layers[2];
    dense(input, a.inputs, a.kernel.data(), a.bias.data(), a.stride, true, hidden1);
    dense(hidden1, b.inputs, b.kernel.data(), b.bias.data(), b.stride, true, hidden2);
    dense(hidden2, c.inputs, c.kernel.data(), c.bias.data(), c.stride, false, linear);
    for (int k = 0; k < kOutputs; ++k) rgb[k] = std::expm1(linear[k]);
}

void NbrdfBrdf::eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query,
                         float* out) const {
    const std::size_t n = query.size();
    if (!(wi.z > 0.f) || !(wo.z > 0.f) || !all_finite(wi) || !all_finite(wo)) {
        std::fill(out, out + n, 0.f);
        return;
    }
    float input[kInputs], rgb[kOutputs];
    network_input(wi, wo, input);
    forward(input, rgb);
    const float cos_o = wo.z;
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t i0 = query.index0[k], i1 = query.index1[k];
        const float w1 = query.weight1[k];
        const float a = i0 < kOutputs ? rgb[i0] : 0.f;
        const float b = i1 < kOutputs ? rgb[i1] : 0.f;
        float v = (w1 == 0.f ? a : (1.f - w1) * a + w1 * b) * cos_o;
        // The value bound keeps every output of an accepted network finite for unit directions;
        // this catches arguments that are not unit vectors (lengths that overflow or vanish).
        if (!std::isfinite(v)) v = 0.f;
        // exp(x) - 1 dips below 0 where the network undershoots a black region.
        if (query.clamp_negative && v < 0.f) v = 0.f;
        out[k] = v;
    }
}

// ---- Sampling ----------------------------------------------------------------------------
// The network has no inverse; cosine-weighted sampling is exact for the diffuse part, never zero
// where the BRDF is not, and keeps pdf and sample trivially consistent (as for MERL files).

float NbrdfBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
    if (!(wi.z > 0.f) || !(wo.z > 0.f)) return 0.f;
    return wo.z * (1.f / kPi);
}

bool NbrdfBrdf::sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                       float* weight) const {
    return sample_cosine_hemisphere(*this, wi, u, query, s, weight);
}

}  // namespace npf
