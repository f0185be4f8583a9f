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

}  // namespace npf::color::detail
