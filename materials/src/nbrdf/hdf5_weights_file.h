// One HDF5 file's floating-point datasets, read from that file and from nothing else: HDF5 can
// make a file read other files, devices and plugins, and each is refused (Hdf5WeightsFile's
// source says how). HDF5's error printing is off while a file is open, and one file is open at a
// time (Debian's HDF5 is not thread-safe). The Neural BRDF reader's (nbrdf_brdf.cpp).
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace npf::nbrdf {

// "21 x 3", "a scalar": a dataset's shape, for messages.
std::string shape_text(const std::vector<hsize_t>& dims);

class Hdf5WeightsFile {
public:
    // Opens `path` (`file_bytes` long) for reading; throws npf::Error naming the file when it is
    // not HDF5 or cannot be read. Holds HDF5 (its lock) until destroyed.
    Hdf5WeightsFile(const std::string& path, std::uint64_t file_bytes);
    ~Hdf5WeightsFile();
    Hdf5WeightsFile(const Hdf5WeightsFile&) = delete;
    Hdf5WeightsFile& operator=(const Hdf5WeightsFile&) = delete;

    // Whether the object `name` ("a/b/c") exists, every link on the way checked.
    bool exists(const std::string& name) const;
    // Reads one floating-point dataset as float, with its shape (rank at most 2, at most
    // NbrdfBrdf::kMaxHiddenUnits squared values). Throws npf::Error naming the file and dataset.
    std::vector<float> read_floats(const std::string& name, std::vector<hsize_t>& dims) const;

private:
    struct Session;
    std::unique_ptr<Session> m_session;
};

}  // namespace npf::nbrdf
