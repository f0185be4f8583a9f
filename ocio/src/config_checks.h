// What npf checks on an OpenColorIO config before OpenColorIO acts on it (docs/color.md,
// "Hostile configs"). OCIO 2.1 trusts its configs: it follows colour space references by
// recursion (a cycle overflows the stack), loads names in quadratic time, expands YAML aliases
// as copies, and opens whatever file a FileTransform names, sizing some tables by the file's
// claims. Each check throws npf::Error naming the config file; the limits are display.h's.
#pragma once

#include <OpenColorIO/OpenColorIO.h>

#include <cstdint>
#include <exception>
#include <string>
#include <vector>

namespace npf::color::detail {

// The config's YAML, before OCIO parses it: nodes with aliases expanded, nesting, entries of
// each list or map, and the number of names (colour spaces, named transforms, aliases). Text
// that is not YAML passes: OCIO then refuses it with its own reason.
void check_config_text(const std::string& text, const std::string& path);

// The loaded config's transform graph: every colour space, look, view transform, named
// transform and display view, with the references of their transforms (ColorSpaceTransform,
// LookTransform, DisplayViewTransform, GroupTransform members), is walked for cycles, depth
// above kMaxReferenceDepth and expansion above kMaxExpandedTransforms; every string OCIO
// resolves context variables in must resolve in a bounded number of steps. Run before
// Config::validate and before any processor.
void check_config_graph(const OCIO_NAMESPACE::Config& config, const std::string& path);

// Every LUT (FileTransform) the display processor from `input` through (display, view) would
// open, resolved as OCIO resolves it: a regular file of at most kMaxLutBytes whose real path is
// under one of the config's search-path folders, with no size claim above what it holds.
void check_display_luts(const OCIO_NAMESPACE::Config& config, const std::string& path,
                        const std::string& input, const std::string& display, const std::string& view);

// OCIO's reason for an exception as one line (its lines joined, long texts cut); where OCIO
// gives none ("Config failed sanitycheck." alone), the cause npf finds in the config.
std::string ocio_reason(const std::exception& e, const OCIO_NAMESPACE::Config* config = nullptr);

// The problem with a LUT file's content ("" for none): a size claim (LUT_3D_SIZE, Length, an
// ICC tag count, a CLF/CTF array dim, ...) for more values than the file's bytes can hold, or
// a token longer than the fixed buffers OCIO's spi1d, spi3d and Discreet readers scan it into.
// Checked whatever the file's extension: OCIO tries every reader on a file its own one fails on.
std::string lut_content_problem(const std::string& bytes);

// ---- Shared by the checks' files -------------------------------------------------------------

// 'name', and 'a', 'b', 'c': names in messages.
std::string quote(const std::string& s);
std::string join_quoted(const std::vector<std::string>& items);

// OCIO's ContainsContextVariables: a '$', or two distinct '%'.
bool has_variables(const std::string& s);

// The folders OCIO looks for a relative LUT name in (Context.cpp, GetAbsoluteSearchPaths): each
// search path (its context variables resolved) trimmed, relative ones under the working dir,
// normalised; the working dir when there is none. config_lut_files.cpp.
std::vector<std::string> search_folders(const std::string& working, const std::vector<std::string>& search_paths);

// One LUT named `src` (`resolved`: its context variables resolved), found and checked as
// check_display_luts says; returns the file's size. config_lut_files.cpp.
std::uint64_t check_lut(const std::string& config_path, const std::string& src, const std::string& resolved,
                        const std::vector<std::string>& folders);

}  // namespace npf::color::detail
