// Shared by the hostile Neural BRDF tests (test_nbrdf_hostile*.cpp, test_nbrdf_value_bound.cpp):
// a small valid network in the Keras layout, written with the HDF5 C API (each dataset plainly
// or by a test's own writer), edited afterwards, and loaded expecting a one-line refusal.
#pragma once

#include "error_of.h"
#include "synthetic_rgl.h"

#include <npf/core/channels.h>
#include <npf/core/vec.h>
#include <npf/materials/nbrdf_brdf.h>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace npf::testing::nbrdf {

using npf::NbrdfBrdf, npf::Vec3;

struct Weights {
    std::vector<hsize_t> dims;
    std::vector<float> values;
};

// Datasets by name, in the Keras layout: dense_k/dense_k/kernel:0 (inputs x units) and bias:0.
using Network = std::map<std::string, Weights>;

inline std::string weight_name(int layer, const char* which) {
    const std::string group = "dense_" + std::to_string(layer);
    return group + "/" + group + "/" + which + ":0";
}

// 6 -> 8 -> 8 -> 3 with seeded weights of the published networks' magnitude.
inline Network small_network(unsigned seed) {
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

inline std::string folder() { return temporary_folder("nbrdf_hostile"); }

// Writes float32 values as dataset `name` of `location`, created with `dcpl`.
inline void write_floats(hid_t location, const std::string& name, const Weights& w, hid_t dcpl = H5P_DEFAULT) {
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
inline std::string write_network(const std::string& path, const Network& net, const std::map<std::string, Writer>& special = {},
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
inline void edit_file(const std::string& path, const std::function<void(hid_t)>& edit) {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0) << path;
    edit(file);
    H5Fclose(file);
}

inline std::vector<char> file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline std::vector<char> float_bytes(const std::vector<float>& values) {
    std::vector<char> bytes(values.size() * sizeof(float));
    std::memcpy(bytes.data(), values.data(), bytes.size());
    return bytes;
}

// Loads `path` expecting an npf::Error: one line, starting with the path, containing `words`,
// and nothing printed by HDF5.
inline void expect_refused(const std::string& path, const std::string& words) {
    ::testing::internal::CaptureStderr();
    const std::string message = error_of([&] { NbrdfBrdf::load(path); });
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find(words), std::string::npos) << "expected \"" << words << "\" in\n" << message;
}

inline npf::ChannelQuery rgb_query() {
    npf::ChannelQuery q = npf::make_channel_query(npf::Channels::rgb(), npf::Channels::rgb(), "test");
    q.clamp_negative = false;
    return q;
}

inline Vec3 direction(double theta, double phi) {
    return {float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))};
}

}  // namespace npf::testing::nbrdf
