// Hostile Neural BRDF files (issue 33): filters from plugins, inflating chunks, unwritten
// datasets, attributes that claim gigabytes, the user block, and the files fuzzing found.
#include <npf/materials/nbrdf_brdf.h>
#include <npf/core/error.h>

#include "nbrdf_files.h"

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

using namespace npf::testing::nbrdf;

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

}  // namespace
