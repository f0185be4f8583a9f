// NPF factor textures, the multi-part OpenEXR files of docs/format.md: the one place they are
// read and written (names: npf_texture_layout.h; the model they hold: npf_model.h).
#pragma once

#include <npf/shading/npf_model.h>
#include <npf/shading/oiio_fwd.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace npf {

// Reads and checks the whole file. Throws npf::Error naming `path` and the problem: a missing
// file, not an OpenEXR file, an OpenEXR file without the NPF attributes, an unknown format
// version, a missing part or channel, sizes that disagree with the attributes, a truncated or
// corrupt file, non-finite values, or negative values where the model has none; and what image
// tools make of a factor texture (docs/farms.md): a TIFF, a single-part copy, or tables that
// no longer match the file's npf:tables_checksum.
NpfModel read_npf_texture(const std::string& path);
// The same, read through a TextureSystem's cache (headers with get_imagespec, pixels with
// get_texels), for a renderer that shades the file through that TextureSystem afterwards.
NpfModel read_npf_texture(const std::string& path, OIIO::TextureSystem& ts);

// Writes `model` to `path` atomically (a temporary beside it, renamed into place): float pixels,
// lossless ZIP compression, every array bit for bit. Throws npf::Error naming `path` when the
// model is inconsistent (NpfModel::validate), a metadata key is empty, repeated or holds a
// control character, or writing fails; no file appears under `path` then. Returns the bytes
// written (also when `path` is a device written through, such as /dev/null).
std::uint64_t write_npf_texture(const NpfModel& model, const std::string& path);

// A cheap sniff that never throws: true when `path` starts with the OpenEXR magic number and its
// part "D" carries an integer npf:format_version (of any value; read_npf_texture judges it).
// Only headers are read.
bool is_npf_texture(const std::string& path);

// Whether the factor texture reader, rather than another material reader, is the one to judge
// `path`: it starts with the OpenEXR magic number (a factor texture, or an image that is not one)
// or with TIFF's (what maketx makes of a factor texture). Reads 4 bytes; never throws.
bool is_npf_texture_or_copy(const std::string& path);

// The OpenEXR magic number (0x762f3101, little-endian) at the start of `head`.
bool has_exr_magic(const unsigned char* head, std::size_t size);
// A TIFF or BigTIFF byte-order mark and magic number at the start of `head`.
bool has_tiff_magic(const unsigned char* head, std::size_t size);

}  // namespace npf
