// Reading a Neural BRDF network's datasets from its own HDF5 file alone (hdf5_weights_file.h).
#include "hdf5_weights_file.h"

#include <npf/materials/nbrdf_brdf.h>

#include <npf/core/error.h>

#include <algorithm>
#include <cstring>
#include <mutex>

namespace npf::nbrdf {

namespace {

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

}  // namespace

std::string shape_text(const std::vector<hsize_t>& dims) {
    if (dims.empty()) return "a scalar";
    std::string text;
    for (std::size_t i = 0; i < dims.size(); ++i)
        text += (i ? " x " : "") + std::to_string(static_cast<unsigned long long>(dims[i]));
    return text;
}

namespace {

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

}  // namespace

struct Hdf5WeightsFile::Session {
    Session(const std::string& path, std::uint64_t file_bytes)
        : lock(hdf5_mutex()), exit_close_stopped(stop_closing_at_exit()), file(open(path), H5Fclose),
          reader(file.get(), path, file_bytes) {}

    // HDF5 closes itself at exit; after some damaged files it cannot (an open that failed half
    // way leaves objects behind) and prints "HDF5: infinite loop closing library" and a list to
    // stderr, after npf's one line. Nothing is written through HDF5, so nothing needs that close.
    // Only possible before HDF5's first call in the process (it fails quietly after): so before
    // QuietHdf5Errors.
    static bool stop_closing_at_exit() {
        static const bool no_close_at_exit = H5dont_atexit() >= 0;
        return no_close_at_exit;
    }

    // Opens the file with HDF5 set up as reading a material needs (under the lock, errors quiet).
    static hid_t open(const std::string& path) {
        // A filter HDF5 does not build in is looked for as a plugin, a shared library from
        // HDF5_PLUGIN_PATH: code that a material file would choose. Off for the whole process (npf
        // reads HDF5 nowhere else); datasets that need such a filter are refused by name.
        H5PLset_loading_state(0);
        if (H5Fis_hdf5(path.c_str()) <= 0) throw Error(path, "not an HDF5 file");
        // The POSIX driver, named rather than taken from the defaults, reads this one file.
        Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
        if (!access.valid() || H5Pset_fapl_sec2(access.get()) < 0)
            throw Error(path, "cannot set up the HDF5 library to read the file");
        const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.get());
        if (file < 0) throw Error(path, "cannot read the HDF5 file (truncated or damaged)");
        return file;
    }

    std::lock_guard<std::mutex> lock;
    bool exit_close_stopped;
    QuietHdf5Errors quiet;
    Handle file;
    const OwnFileReader reader;
};

Hdf5WeightsFile::Hdf5WeightsFile(const std::string& path, std::uint64_t file_bytes)
    : m_session(std::make_unique<Session>(path, file_bytes)) {}

Hdf5WeightsFile::~Hdf5WeightsFile() = default;

bool Hdf5WeightsFile::exists(const std::string& name) const { return m_session->reader.exists(name); }

std::vector<float> Hdf5WeightsFile::read_floats(const std::string& name, std::vector<hsize_t>& dims) const {
    return m_session->reader.read_floats(name, dims);
}

}  // namespace npf::nbrdf
