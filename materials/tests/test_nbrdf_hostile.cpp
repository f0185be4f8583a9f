// Hostile Neural BRDF files (issue 33): a material file is read from itself alone, and a network
// whose outputs can overflow is refused. Each file is written here with the HDF5 C API from a
// small valid network, then made hostile one way: external storage, external and soft links,
// virtual datasets, link loops, a filter from a plugin, an inflating chunk, a variable-length
// attribute that claims gigabytes, weights whose combination overflows. Every test but the last
// two failed on the reader before the checks it exercises (the plain reader read the other file,
// the FIFO, the plugin's absence as damage, and accepted the overflowing networks).
// Here external storage, links and virtual datasets; filters, attributes and what fuzzing found:
// test_nbrdf_hostile_filters.cpp; the value bound: test_nbrdf_value_bound.cpp.
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

}  // namespace
