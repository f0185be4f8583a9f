// Hostile Neural BRDF files (issue 33): a material file is read from itself alone, and a network
// whose outputs can overflow is refused. Each file is written here with the HDF5 C API from a
// small valid network, then made hostile one way: external storage, external and soft links,
// virtual datasets, link loops, a filter from a plugin, an inflating chunk, a variable-length
// attribute that claims gigabytes, weights whose combination overflows. Every test but the last
// two failed on the reader before the checks it exercises (the plain reader read the other file,
// the FIFO, the plugin's absence as damage, and accepted the overflowing networks).
#include <npf/materials/nbrdf_brdf.h>
#include <npf/core/error.h>

#include <error_of.h>
#include <run_tool.h>
#include <synthetic_rgl.h>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using npf::NbrdfBrdf;
using npf::Vec3;
using npf::testing::error_of;

// ---- Writing networks -------------------------------------------------------------------

struct Weights {
    std::vector<hsize_t> dims;
    std::vector<float> values;
};

// Datasets by name, in the Keras layout: dense_k/dense_k/kernel:0 (inputs x units) and bias:0.
using Network = std::map<std::string, Weights>;

std::string weight_name(int layer, const char* which) {
    const std::string group = "dense_" + std::to_string(layer);
    return group + "/" + group + "/" + which + ":0";
}

// 6 -> 8 -> 8 -> 3 with seeded weights of the published networks' magnitude.
Network small_network(unsigned seed) {
    std::mt19937 rng(seed);
    auto uniform = [&](float scale) { return scale * (float(rng() % 20001) / 10000.f - 1.f); };
    Network net;
    const int sizes[] = {6, 8, 8, 3};
    for (int k = 0; k < 3; ++k) {
        Weights kernel{{hsize_t(sizes[k]), hsize_t(sizes[k + 1])}, {}}, bias{{hsize_t(sizes[k + 1])}, {}};
        kernel.values.resize(std::size_t(sizes[k]) * sizes[k + 1]);
        for (float& w : kernel.values) w = uniform(k == 0 ? 1.f : 0.5f);
        bias.values.resize(std::size_t(sizes[k + 1]));
        for (float& b : bias.values) b = uniform(0.2f);
        net[weight_name(k + 1, "kernel")] = kernel;
        net[weight_name(k + 1, "bias")] = bias;
    }
    return net;
}

std::string folder() { return npf::testing::temporary_folder("nbrdf_hostile"); }

// Writes float32 values as dataset `name` of `location`, created with `dcpl`.
void write_floats(hid_t location, const std::string& name, const Weights& w, hid_t dcpl = H5P_DEFAULT) {
    const hid_t space = H5Screate_simple(int(w.dims.size()), w.dims.data(), nullptr);
    const hid_t dataset = H5Dcreate2(location, name.c_str(), H5T_IEEE_F32LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ASSERT_GE(dataset, 0) << name;
    EXPECT_GE(H5Dwrite(dataset, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, w.values.data()), 0) << name;
    H5Dclose(dataset);
    H5Sclose(space);
}

// How one dataset is written instead of plainly.
using Writer = std::function<void(hid_t file, const std::string& name, const Weights& w)>;

// Writes `net` to `path`: the groups, then each dataset, plainly unless `special` names it.
std::string write_network(const std::string& path, const Network& net, const std::map<std::string, Writer>& special = {},
                          hid_t fcpl = H5P_DEFAULT) {
    const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
    EXPECT_GE(file, 0) << path;
    for (int k = 1; k <= 3; ++k) {
        const std::string group = "dense_" + std::to_string(k);
        H5Gclose(H5Gcreate2(file, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
        H5Gclose(H5Gcreate2(file, (group + "/" + group).c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    }
    for (const auto& [name, weights] : net) {
        const auto it = special.find(name);
        if (it != special.end())
            it->second(file, name, weights);
        else
            write_floats(file, name, weights);
    }
    H5Fclose(file);
    return path;
}

// Opens `path` for writing and applies `edit` to it.
void edit_file(const std::string& path, const std::function<void(hid_t)>& edit) {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0) << path;
    edit(file);
    H5Fclose(file);
}

std::vector<char> file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<char> float_bytes(const std::vector<float>& values) {
    std::vector<char> bytes(values.size() * sizeof(float));
    std::memcpy(bytes.data(), values.data(), bytes.size());
    return bytes;
}

// Loads `path` expecting an npf::Error: one line, starting with the path, containing `words`,
// and nothing printed by HDF5.
void expect_refused(const std::string& path, const std::string& words) {
    ::testing::internal::CaptureStderr();
    const std::string message = error_of([&] { NbrdfBrdf::load(path); });
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find(words), std::string::npos) << "expected \"" << words << "\" in\n" << message;
}

npf::ChannelQuery rgb_query() {
    npf::ChannelQuery q = npf::make_channel_query(npf::Channels::rgb(), npf::Channels::rgb(), "test");
    q.clamp_negative = false;
    return q;
}

Vec3 direction(double theta, double phi) {
    return {float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))};
}

// ---- External storage -------------------------------------------------------------------

TEST(NbrdfHostile, ExternalStorageInAnotherFile) {
    const std::string dir = folder(), elsewhere = dir + "/elsewhere.bin";
    const Network net = small_network(1);
    const std::string kernel = weight_name(1, "kernel");
    const Writer writer = [&](hid_t file, const std::string& name, const Weights& w) {
        const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
        H5Pset_external(dcpl, elsewhere.c_str(), 0, hsize_t(w.values.size() * sizeof(float)));
        write_floats(file, name, w, dcpl);  // the values go to elsewhere.bin
        H5Pclose(dcpl);
    };
    const std::string path = write_network(dir + "/external.h5", net, {{kernel, writer}});
    ASSERT_EQ(file_bytes(elsewhere), float_bytes(net.at(kernel).values));
    expect_refused(path, "dataset dense_1/dense_1/kernel:0 uses external storage (file " + elsewhere +
                             "): a material is read from its own file alone");
}

// External storage on a FIFO made every command wait for a writer forever. Here a writer holds
// the right bytes in the pipe (so that the old reader could not hang the test): the reader must
// refuse the file without taking them.
TEST(NbrdfHostile, ExternalStorageOnAFifoIsNeverOpened) {
    const std::string dir = folder(), fifo = dir + "/pipe";
    const Network net = small_network(2);
    const std::string kernel = weight_name(2, "kernel");
    const std::vector<char> bytes = float_bytes(net.at(kernel).values);
    const Writer writer = [&](hid_t file, const std::string& name, const Weights& w) {
        const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
        H5Pset_external(dcpl, fifo.c_str(), 0, hsize_t(bytes.size()));
        write_floats(file, name, w, dcpl);
        H5Pclose(dcpl);
    };
    const std::string path = write_network(dir + "/fifo.h5", net, {{kernel, writer}});
    ASSERT_EQ(::unlink(fifo.c_str()), 0);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const int pipe = ::open(fifo.c_str(), O_RDWR | O_NONBLOCK);
    ASSERT_GE(pipe, 0);
    ASSERT_EQ(::write(pipe, bytes.data(), bytes.size()), ssize_t(bytes.size()));
    expect_refused(path, "dataset dense_2/dense_2/kernel:0 uses external storage (file " + fifo + ")");
    int waiting = 0;
    EXPECT_EQ(::ioctl(pipe, FIONREAD, &waiting), 0);
    EXPECT_EQ(waiting, int(bytes.size()));  // nothing taken
    ::close(pipe);
}

// A relative external name points wherever the working directory makes it (the review's file
// named ../../etc/hostname). Here it names a folder that does not exist, in case a version of
// HDF5 wrote fill values on creation; the dataset is created without fill, allocated late.
TEST(NbrdfHostile, ExternalStorageOutsideTheFolder) {
    const std::string dir = folder();
    const Writer writer = [&](hid_t file, const std::string& name, const Weights& w) {
        const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
        H5Pset_external(dcpl, "../../npf-no-such-folder/hostname", 0, hsize_t(w.values.size() * sizeof(float)));
        H5Pset_fill_time(dcpl, H5D_FILL_TIME_NEVER);
        H5Pset_alloc_time(dcpl, H5D_ALLOC_TIME_LATE);
        const hid_t space = H5Screate_simple(int(w.dims.size()), w.dims.data(), nullptr);
        H5Dclose(H5Dcreate2(file, name.c_str(), H5T_IEEE_F32LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT));
        H5Sclose(space);
        H5Pclose(dcpl);
    };
    const std::string path = write_network(dir + "/hostname.h5", small_network(3), {{weight_name(3, "bias"), writer}});
    expect_refused(path, "dataset dense_3/dense_3/bias:0 uses external storage (file ../../npf-no-such-folder/hostname): "
                         "a material is read from its own file alone");
}

// ---- Links ------------------------------------------------------------------------------

TEST(NbrdfHostile, ExternalLinkToAnotherMaterial) {
    const std::string dir = folder();
    const std::string other = write_network(dir + "/other.h5", small_network(5));
    const std::string group = write_network(dir + "/group_link.h5", small_network(4));
    edit_file(group, [&](hid_t file) {
        ASSERT_GE(H5Ldelete(file, "dense_2", H5P_DEFAULT), 0);
        ASSERT_GE(H5Lcreate_external(other.c_str(), "/dense_2", file, "dense_2", H5P_DEFAULT, H5P_DEFAULT), 0);
    });
    expect_refused(group, "dense_2 is an external link (to " + other + ":/dense_2): a material is read from its own file alone");

    const std::string bias = write_network(dir + "/dataset_link.h5", small_network(4));
    edit_file(bias, [&](hid_t file) {
        const std::string name = weight_name(3, "bias");
        ASSERT_GE(H5Ldelete(file, name.c_str(), H5P_DEFAULT), 0);
        ASSERT_GE(H5Lcreate_external(other.c_str(), ("/" + name).c_str(), file, name.c_str(), H5P_DEFAULT, H5P_DEFAULT), 0);
    });
    expect_refused(bias, "dense_3/dense_3/bias:0 is an external link (to " + other + ":/dense_3/dense_3/bias:0)");
}

TEST(NbrdfHostile, SoftLink) {
    const std::string path = write_network(folder() + "/soft.h5", small_network(6));
    edit_file(path, [&](hid_t file) {
        const std::string name = weight_name(2, "kernel");
        ASSERT_GE(H5Lmove(file, name.c_str(), file, "stash", H5P_DEFAULT, H5P_DEFAULT), 0);
        ASSERT_GE(H5Lcreate_soft("/stash", file, name.c_str(), H5P_DEFAULT, H5P_DEFAULT), 0);
    });
    expect_refused(path, "dense_2/dense_2/kernel:0 is a soft link (to /stash): a material is read through its own hard "
                         "links alone");
}

// dense_1/dense_1 is the group dense_1 itself: the kernel is found through the loop.
TEST(NbrdfHostile, LinkLoop) {
    const std::string path = write_network(folder() + "/loop.h5", small_network(7));
    edit_file(path, [&](hid_t file) {
        for (const char* which : {"kernel", "bias"}) {
            const std::string name = weight_name(1, which);
            const std::string moved = std::string("dense_1/") + which + ":0";
            ASSERT_GE(H5Lmove(file, name.c_str(), file, moved.c_str(), H5P_DEFAULT, H5P_DEFAULT), 0);
        }
        ASSERT_GE(H5Ldelete(file, "dense_1/dense_1", H5P_DEFAULT), 0);
        ASSERT_GE(H5Lcreate_hard(file, "dense_1", file, "dense_1/dense_1", H5P_DEFAULT, H5P_DEFAULT), 0);
    });
    expect_refused(path, "dense_1 has 2 hard links to it (a link loop, or one object under several names)");
}

TEST(NbrdfHostile, OneDatasetUnderTwoNames) {
    const std::string path = write_network(folder() + "/twice.h5", small_network(8));
    edit_file(path, [&](hid_t file) {
        ASSERT_GE(H5Lcreate_hard(file, weight_name(3, "bias").c_str(), file, "bias_again", H5P_DEFAULT, H5P_DEFAULT), 0);
    });
    expect_refused(path, "dense_3/dense_3/bias:0 has 2 hard links to it");
}

// ---- Virtual datasets -------------------------------------------------------------------

TEST(NbrdfHostile, VirtualDataset) {
    const std::string dir = folder(), source = dir + "/source.h5";
    const Network net = small_network(9);
    const std::string kernel = weight_name(1, "kernel");
    {
        const hid_t file = H5Fcreate(source.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
        write_floats(file, "data", net.at(kernel));
        H5Fclose(file);
    }
    auto mapped_from = [&](const std::string& file_name, const std::string& dataset) -> Writer {
        return [=](hid_t file, const std::string& name, const Weights& w) {
            if (file_name == ".") write_floats(file, dataset, w);
            const hid_t space = H5Screate_simple(int(w.dims.size()), w.dims.data(), nullptr);
            const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
            ASSERT_GE(H5Pset_virtual(dcpl, space, file_name.c_str(), dataset.c_str(), space), 0);
            H5Dclose(H5Dcreate2(file, name.c_str(), H5T_IEEE_F32LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT));
            H5Pclose(dcpl);
            H5Sclose(space);
        };
    };
    const std::string other = write_network(dir + "/virtual.h5", net, {{kernel, mapped_from(source, "/data")}});
    expect_refused(other, "dataset dense_1/dense_1/kernel:0 is a virtual dataset (mapped from " + source +
                              ":/data): a material is read from its own file alone");
    // Mapped from the same file: still an indirection HDF5 resolves by opening files by name.
    const std::string same = write_network(dir + "/virtual_same.h5", net, {{kernel, mapped_from(".", "/stash")}});
    expect_refused(same, "dataset dense_1/dense_1/kernel:0 is a virtual dataset (mapped from .:/stash)");
}

// ---- Filters ----------------------------------------------------------------------------

constexpr H5Z_filter_t kTestFilter = 40000;

size_t identity_filter(unsigned, size_t, const unsigned[], size_t nbytes, size_t*, void**) { return nbytes; }

// A filter that is not built into HDF5 is looked for as a plugin, a shared library. The file
// is written with the filter registered in this process, which then forgets it.
TEST(NbrdfHostile, FilterFromAPlugin) {
    const H5Z_class2_t filter = {H5Z_CLASS_T_VERS, kTestFilter, 1, 1, "npf test filter", nullptr, nullptr, identity_filter};
    ASSERT_GE(H5Zregister(&filter), 0);
    const std::string kernel = weight_name(1, "kernel");
    const Writer writer = [](hid_t file, const std::string& name, const Weights& w) {
        const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
        H5Pset_chunk(dcpl, int(w.dims.size()), w.dims.data());
        H5Pset_filter(dcpl, kTestFilter, H5Z_FLAG_MANDATORY, 0, nullptr);
        write_floats(file, name, w, dcpl);
        H5Pclose(dcpl);
    };
    const std::string path = write_network(folder() + "/plugin.h5", small_network(10), {{kernel, writer}});
    ASSERT_GE(H5Zunregister(kTestFilter), 0);
    expect_refused(path, "dataset dense_1/dense_1/kernel:0 needs filter 40000 (npf test filter), which is not built "
                         "into HDF5: plugins are never loaded for a material");
    unsigned loading = ~0u;
    ASSERT_GE(H5PLget_loading_state(&loading), 0);
    EXPECT_EQ(loading, 0u) << "the reader leaves HDF5's plugin loading on";
}

// Chunked, shuffled, deflated and checksummed, as h5py can write: read as before, same values.
TEST(NbrdfHostile, BuiltInFiltersStillRead) {
    const std::string dir = folder();
    const Network net = small_network(11);
    const std::string plain = write_network(dir + "/plain.h5", net);
    std::map<std::string, Writer> compressed;
    for (const auto& entry : net)
        compressed[entry.first] = [](hid_t file, const std::string& name, const Weights& w) {
            const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
            std::vector<hsize_t> chunk = w.dims;
            chunk[0] = std::max<hsize_t>(1, chunk[0] / 2);  // several chunks, the last partial
            H5Pset_chunk(dcpl, int(chunk.size()), chunk.data());
            H5Pset_shuffle(dcpl);
            H5Pset_deflate(dcpl, 6);
            H5Pset_fletcher32(dcpl);
            write_floats(file, name, w, dcpl);
            H5Pclose(dcpl);
        };
    const std::string filtered = write_network(dir + "/filtered.h5", net, compressed);
    const auto a = NbrdfBrdf::load(plain), b = NbrdfBrdf::load(filtered);
    for (double t : {0.1, 0.7, 1.3})
        for (double p : {0.0, 2.0, 4.0}) {
            float va[3], vb[3];
            a->eval_cos(direction(0.4, 0.3), direction(t, p), rgb_query(), va);
            b->eval_cos(direction(0.4, 0.3), direction(t, p), rgb_query(), vb);
            EXPECT_EQ(std::memcmp(va, vb, sizeof va), 0);
        }
}

// Deflate's output grows until its stream ends: a chunk of 256 bytes of values stored as a
// stream of 16 MB of zeros. HDF5 itself compresses the zeros (the tests do not link zlib).
TEST(NbrdfHostile, InflatingChunk) {
    const std::string dir = folder(), scratch = dir + "/zeros.h5";
    std::vector<char> stream;
    {
        const hid_t file = H5Fcreate(scratch.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
        const Weights zeros{{hsize_t(4) << 20}, std::vector<float>(std::size_t(4) << 20, 0.f)};
        const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
        H5Pset_chunk(dcpl, 1, zeros.dims.data());
        H5Pset_deflate(dcpl, 9);
        write_floats(file, "zeros", zeros, dcpl);
        H5Pclose(dcpl);
        const hid_t dataset = H5Dopen2(file, "zeros", H5P_DEFAULT);
        const hsize_t origin[1] = {0};
        hsize_t stored = 0;
        ASSERT_GE(H5Dget_chunk_storage_size(dataset, origin, &stored), 0);
        stream.resize(stored);
        std::uint32_t mask = 0;
        ASSERT_GE(H5Dread_chunk(dataset, H5P_DEFAULT, origin, &mask, stream.data()), 0);
        H5Dclose(dataset);
        H5Fclose(file);
    }
    const std::string kernel = weight_name(2, "kernel");
    const Writer writer = [&](hid_t file, const std::string& name, const Weights& w) {
        const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
        H5Pset_chunk(dcpl, int(w.dims.size()), w.dims.data());
        H5Pset_deflate(dcpl, 9);
        const hid_t space = H5Screate_simple(int(w.dims.size()), w.dims.data(), nullptr);
        const hid_t dataset = H5Dcreate2(file, name.c_str(), H5T_IEEE_F32LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
        const hsize_t origin[2] = {0, 0};
        EXPECT_GE(H5Dwrite_chunk(dataset, H5P_DEFAULT, 0, origin, stream.size(), stream.data()), 0);
        H5Dclose(dataset);
        H5Sclose(space);
        H5Pclose(dcpl);
    };
    const std::string path = write_network(dir + "/bomb.h5", small_network(12), {{kernel, writer}});
    expect_refused(path, "dataset dense_2/dense_2/kernel:0 stores " + std::to_string(stream.size()) +
                             " bytes for a chunk of 256 bytes of values (file damaged)");
}

// A dataset never written reads as its fill value, from a message whose size HDF5 1.10 trusts.
TEST(NbrdfHostile, DatasetNeverWritten) {
    const Writer writer = [](hid_t file, const std::string& name, const Weights& w) {
        const hid_t space = H5Screate_simple(int(w.dims.size()), w.dims.data(), nullptr);
        H5Dclose(H5Dcreate2(file, name.c_str(), H5T_IEEE_F32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
        H5Sclose(space);
    };
    const std::string path = write_network(folder() + "/unwritten.h5", small_network(13), {{weight_name(1, "bias"), writer}});
    expect_refused(path, "dataset dense_1/dense_1/bias:0 holds no stored values (never written, or file damaged)");
}

// ---- Attributes and the user block ------------------------------------------------------

std::size_t peak_memory_kib() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return std::size_t(usage.ru_maxrss);
}

// Keras writes keras_version as a variable-length string: its length is a 4-byte count beside a
// reference into the file's global heap, and HDF5 allocates (and fills) what the count claims.
// Claiming 2^31 - 1 made the old reader take 4 GB and 16 s.
TEST(NbrdfHostile, VariableLengthAttributeClaimingGigabytes) {
    const std::string path = write_network(folder() + "/vlen.h5", small_network(14));
    edit_file(path, [](hid_t file) {
        const hid_t type = H5Tcopy(H5T_C_S1);
        H5Tset_size(type, H5T_VARIABLE);
        const hid_t space = H5Screate(H5S_SCALAR);
        const hid_t attribute = H5Acreate2(file, "keras_version", type, space, H5P_DEFAULT, H5P_DEFAULT);
        const char* version = "2.2.4";
        ASSERT_GE(H5Awrite(attribute, type, &version), 0);
        H5Aclose(attribute);
        H5Sclose(space);
        H5Tclose(type);
    });
    // The stored reference: length 5 (little-endian), then the heap collection's address.
    std::vector<char> bytes = file_bytes(path);
    const std::string heap = "GCOL";
    const auto at = std::search(bytes.begin(), bytes.end(), heap.begin(), heap.end());
    ASSERT_NE(at, bytes.end());
    const std::uint64_t heap_address = std::uint64_t(at - bytes.begin());
    char reference[12] = {5, 0, 0, 0};
    std::memcpy(reference + 4, &heap_address, 8);
    const auto ref = std::search(bytes.begin(), bytes.end(), reference, reference + 12);
    ASSERT_NE(ref, bytes.end());
    const std::uint32_t claimed = 0x7fffffff;
    std::memcpy(&*ref, &claimed, 4);
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));

    const std::size_t before = peak_memory_kib();
    const auto brdf = NbrdfBrdf::load(path);
    EXPECT_LT(peak_memory_kib() - before, std::size_t(1) << 20) << "loading raised the peak memory by over 1 GiB";
}

// A user block (bytes before the HDF5 superblock) is opaque to HDF5: harmless, still read.
TEST(NbrdfHostile, UserBlockIsHarmless) {
    const hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
    H5Pset_userblock(fcpl, 512);
    const std::string path = write_network(folder() + "/user_block.h5", small_network(15), {}, fcpl);
    H5Pclose(fcpl);
    EXPECT_EQ(NbrdfBrdf::load(path)->hidden1_units(), 8);
}

// ---- Found by fuzzing (fuzz/corpus/nbrdf/) ----------------------------------------------

std::string corpus_file(const char* name) { return std::string(NPF_SOURCE_DIR) + "/fuzz/corpus/nbrdf/" + name; }

// A chunk whose index records 45 bytes for its 48 bytes of values (no filter): HDF5 1.10 read
// the 48 from a buffer of the 45 (AddressSanitizer: heap-buffer-overflow in H5VM_memcpyvv,
// under H5Dread). H5Dget_chunk_storage_size reports 48 for it: the index's record is checked.
TEST(NbrdfHostile, ChunkRecordedSmallerThanItsValues) {
    expect_refused(corpus_file("chunk_recorded_smaller.h5"),
                   "dataset dense_1/dense_1/kernel:0 stores 45 bytes for a chunk of 48 bytes of values (file damaged)");
}

// The root group's heap address made absurd: HDF5's open fails half way and, at exit, could not
// close what it left ("HDF5: infinite loop closing library" and a list, after npf's line).
TEST(NbrdfHostile, DamagedFileGivesOneLineUpToExit) {
    const npf::testing::ToolRun run = npf::testing::run_tool({"info", corpus_file("hdf5_cannot_close_at_exit.h5")});
    EXPECT_EQ(run.status, 1) << npf::testing::describe(run);
    EXPECT_EQ(npf::testing::lines_of(run.err).size(), 1u) << npf::testing::describe(run);
    EXPECT_TRUE(npf::testing::contains(run.err, "cannot read the HDF5 file (truncated or damaged)"))
        << npf::testing::describe(run);
}

// ---- The value bound --------------------------------------------------------------------

// The largest f_r cos(theta_i) cos(theta_o) over random pairs (grazing ones included), and
// whether every value was finite.
double sampled_maximum(const npf::Brdf& brdf, unsigned seed, int pairs, bool& all_finite) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double best = 0;
    all_finite = true;
    for (int n = 0; n < pairs; ++n) {
        // Uniform in cos theta, plus a share of near-horizon and near-normal directions.
        auto draw = [&] {
            const double r = u(rng);
            const double cos_theta = r < 0.1 ? 1e-4 * u(rng) : r < 0.2 ? 1 - 1e-4 * u(rng) : u(rng);
            return direction(std::acos(cos_theta), 2 * M_PI * u(rng));
        };
        const Vec3 wi = draw(), wo = draw();
        if (!(wi.z > 0.f) || !(wo.z > 0.f)) continue;
        float out[3];
        brdf.eval_cos(wi, wo, rgb_query(), out);
        for (float v : out) {
            all_finite = all_finite && std::isfinite(v);
            best = std::max(best, double(std::fabs(v)) * wi.z);
        }
    }
    return best;
}

TEST(NbrdfValueBound, OutputBiasThatOverflowsIsRefused) {
    Network net = small_network(20);
    net[weight_name(3, "bias")].values = {1e11f, 0.f, 0.f};  // each weight finite; exp(1e11) is not
    const std::string path = write_network(folder() + "/bias_1e11.h5", net);
    expect_refused(path, "can give f_r cos(theta_i) cos(theta_o) up to infinity 1/sr (exp(output) - 1 by interval arithmetic");
}

// With a zero output kernel f_r = exp(b) - 1 everywhere, largest at normal incidence on both
// sides (cosines 1): the cap of 1e12 lies between b = 27 and b = 28.
TEST(NbrdfValueBound, ConstantNetworkAtTheCap) {
    for (const float b : {27.f, 28.f}) {
        Network net = small_network(21);
        std::fill(net[weight_name(3, "kernel")].values.begin(), net[weight_name(3, "kernel")].values.end(), 0.f);
        net[weight_name(3, "bias")].values = {b, b, b};
        const std::string path = write_network(folder() + "/constant.h5", net);
        const double value = std::expm1(double(b));
        if (value > npf::kMaxMaterialValue) {
            expect_refused(path, "above the 1e12 a material may reach: refused as corrupt");
            continue;
        }
        const auto brdf = NbrdfBrdf::load(path);
        EXPECT_GE(brdf->info().value_bound, value * (1 - 1e-6));
        EXPECT_LE(brdf->info().value_bound, value * 1.001);  // exact at the normal, up to rounding margins
        float out[3];
        brdf->eval_cos(Vec3(0.f, 0.f, 1.f), Vec3(0.f, 0.f, 1.f), rgb_query(), out);
        EXPECT_NEAR(out[0], value, value * 1e-6);
    }
}

// Hidden units past float's range give inf, then inf x 0 = NaN, which eval turned into a silent 0.
TEST(NbrdfValueBound, HiddenUnitsBeyondFloatAreRefused) {
    Network net = small_network(22);
    for (float& w : net[weight_name(1, "kernel")].values) w = 3e38f;
    std::fill(net[weight_name(2, "kernel")].values.begin(), net[weight_name(2, "kernel")].values.end(), 0.f);
    const std::string path = write_network(folder() + "/huge_hidden.h5", net);
    expect_refused(path, "a unit of the network can reach");
    expect_refused(path, "beyond the 1e30 within which its float evaluation cannot overflow: refused as corrupt");
}

// The bound holds: no sampled pair exceeds it; and it is not absurdly loose: within 10x of the
// sampled maximum up to the published width, within 100x for a wide network of large weights
// (measured: 1.8x, 2.0x, 38x, 3.9x; intervals lose more through wider layers).
TEST(NbrdfValueBound, HoldsOverSampledPairs) {
    for (const auto& [width, scale] : {std::pair{8, 1.f}, std::pair{21, 1.f}, std::pair{40, 2.f}, std::pair{3, 4.f}}) {
        std::mt19937 rng{unsigned(width)};
        Network net;
        const int sizes[] = {6, width, width, 3};
        for (int k = 0; k < 3; ++k) {
            Weights kernel{{hsize_t(sizes[k]), hsize_t(sizes[k + 1])}, std::vector<float>(std::size_t(sizes[k]) * sizes[k + 1])};
            Weights bias{{hsize_t(sizes[k + 1])}, std::vector<float>(std::size_t(sizes[k + 1]))};
            std::normal_distribution<float> normal(0.f, scale / std::sqrt(float(sizes[k])));
            for (float& w : kernel.values) w = normal(rng);
            for (float& b : bias.values) b = 0.2f * normal(rng);
            net[weight_name(k + 1, "kernel")] = kernel;
            net[weight_name(k + 1, "bias")] = bias;
        }
        const auto brdf = NbrdfBrdf::load(write_network(folder() + "/random.h5", net));
        bool finite = false;
        const double sampled = sampled_maximum(*brdf, 5, 40000, finite);
        SCOPED_TRACE("width " + std::to_string(width) + ": bound " + std::to_string(brdf->info().value_bound) +
                     ", sampled " + std::to_string(sampled));
        EXPECT_TRUE(finite);
        EXPECT_LE(sampled, brdf->info().value_bound);
        EXPECT_LE(brdf->info().value_bound, (width <= 21 ? 10 : 100) * sampled);
    }
}

// ---- The published networks: unchanged --------------------------------------------------

// eval_cos at six pairs, as the reader gave them before the checks (bit for bit), and their
// value bounds: above every sampled value, and within the factor the bounding stops at.
TEST(NbrdfSharedData, EvaluateAsBeforeAndBounded) {
    const Vec3 pairs[6][2] = {
        {{0.f, 0.f, 1.f}, {0.f, 0.f, 1.f}},
        {{0.6f, 0.f, 0.8f}, {-0.6f, 0.f, 0.8f}},
        {{0.6f, 0.f, 0.8f}, {0.f, -0.96f, 0.28f}},
        {{0.5f, 0.5f, 0.70710677f}, {-0.8f, 0.1f, 0.59160799f}},
        {{0.99f, 0.1f, 0.099498743f}, {-0.99f, -0.1f, 0.099498743f}},
        {{0.f, -0.96f, 0.28f}, {0.99f, 0.1f, 0.099498743f}},
    };
    struct Expected {
        const char* material;
        float values[6][3];
        double largest_bound;  // measured 0.396, 1285, 171, 0.632, 38.9
    };
    const Expected expected[] = {
        {"acrylic_felt_green_rgb",
         {{0x1.a96a5ap-5f, 0x1.6dd02ap-4f, 0x1.0935p-6f},
          {0x1.8898bcp-5f, 0x1.4ae08p-4f, 0x1.0f2bbcp-6f},
          {0x1.52db46p-7f, 0x1.5f5614p-6f, 0x1.a974d2p-9f},
          {0x1.cab818p-6f, 0x1.b8223ap-5f, 0x1.0decbcp-7f},
          {0x1.874f5cp-1f, 0x1.ca6978p-1f, 0x1.e8e1c2p-3f},
          {0x1.f1f452p-9f, 0x1.ba5a14p-8f, 0x1.68aafcp-10f}},
         0.5},
        {"cg_sunflower_rgb",
         {{0x1.7c6708p+7f, 0x1.26de68p+7f, 0x1.9b7e26p+6f},
          {0x1.7f21c2p+7f, 0x1.50249ap+7f, 0x1.1a72dep+7f},
          {0x1.114bd4p-4f, 0x1.fbd82p-6f, 0x0p+0f},
          {0x1.4ac688p-3f, 0x1.3c3bacp-4f, 0x0p+0f},
          {0x1.903d38p+8f, 0x1.8d83b2p+8f, 0x1.90d134p+8f},
          {0x1.2a90eap-8f, 0x1.546dbp-9f, 0x0p+0f}},
         1500},
        {"ilm_l3_37_metallic_rgb",
         {{0x1.0e293p+6f, 0x1.16129ap+6f, 0x1.14156cp+6f},
          {0x1.69cffep+6f, 0x1.73df16p+6f, 0x1.73bb76p+6f},
          {0x1.e0fb6cp-10f, 0x1.f1b282p-10f, 0x1.e174e2p-10f},
          {0x1.2fca04p-5f, 0x1.34c59ap-5f, 0x1.312b6cp-5f},
          {0x1.6b6f48p+7f, 0x1.776314p+7f, 0x1.85eac4p+7f},
          {0x1.00d714p-14f, 0x1.2c89d4p-14f, 0x1.1a86ap-14f}},
         200},
        {"paper_white_rgb",
         {{0x1.11d47ep-2f, 0x1.1660a8p-2f, 0x1.469adep-2f},
          {0x1.d2cb6ap-3f, 0x1.d77cfep-3f, 0x1.0f27dcp-2f},
          {0x1.1e771cp-4f, 0x1.21a3c4p-4f, 0x1.4f5b7ep-4f},
          {0x1.51fdc4p-3f, 0x1.54c148p-3f, 0x1.85f64p-3f},
          {0x1.bffebap-3f, 0x1.b1a3a4p-3f, 0x1.b16196p-3f},
          {0x1.50ad4ap-7f, 0x1.4e1d9ap-7f, 0x1.7144b4p-7f}},
         0.75},
        {"vch_golden_yellow_rgb",
         {{0x1.4c125ap+3f, 0x1.452a9cp+2f, 0x1.5fbb5ap-10f},
          {0x1.065472p+3f, 0x1.06e93p+2f, 0x1.2f863ap-6f},
          {0x1.c4d05ep-9f, 0x1.aa0b02p-9f, 0x1.23b014p-10f},
          {0x1.96f9acp-7f, 0x1.8ec3bcp-7f, 0x1.d285d2p-9f},
          {0x1.ada692p+5f, 0x1.706a68p+5f, 0x1.394d5ap+5f},
          {0x1.646514p-11f, 0x1.315afcp-11f, 0x1.c8cbf6p-13f}},
         50},
    };
    int checked = 0;
    for (const Expected& e : expected) {
        const std::string path = npf::testing::shared_data_file(std::string("nbrdf/") + e.material + ".h5");
        if (path.empty()) continue;
        SCOPED_TRACE(e.material);
        const auto brdf = NbrdfBrdf::load(path);
        const npf::ChannelQuery q = brdf->native_query();
        for (int n = 0; n < 6; ++n) {
            float out[3];
            brdf->eval_cos(pairs[n][0], pairs[n][1], q, out);
            for (int c = 0; c < 3; ++c) EXPECT_EQ(out[c], e.values[n][c]) << "pair " << n << ", channel " << c;
        }
        bool finite = false;
        const double sampled = sampled_maximum(*brdf, 3, 40000, finite);
        EXPECT_TRUE(finite);
        EXPECT_LE(sampled, brdf->info().value_bound);
        EXPECT_LE(brdf->info().value_bound, e.largest_bound);
        ++checked;
    }
    if (checked == 0) GTEST_SKIP() << "nbrdf/*.h5 not found in the shared data folder";
}

}  // namespace
