// Reading text inputs within bounds (docs/reliability.md, "Bounded text"): every line-based input
// (direction pairs, spectra, recipes, batch and colour configurations) has a cap on its whole size
// and on one line, refused at once with the file and the line named, so that /dev/zero, a file
// of one endless line or a huge file costs what the cap allows and not what the input holds.
// A NUL byte is refused too: no text format npf reads has one, and a binary file named as text
// would otherwise be parsed as garbage.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace npf {

struct TextBounds {
    std::uint64_t max_bytes;     // the whole input
    std::size_t max_line_bytes;  // one line, without its newline
};

// The caps, one place for all readers. A recipe or an edit recipe is a page of YAML; a batch
// configuration lists a library (a thousand materials are ~100 kB); a colour configuration of a
// studio is tens of kB; a tabulated spectrum at 0.1 nm from 200 to 2500 nm is ~0.5 MB; a
// direction file is a stream of any number of pairs, so only its lines are short.
inline constexpr TextBounds kRecipeTextBounds{std::uint64_t(1) << 20, std::size_t(1) << 16};
inline constexpr TextBounds kConfigTextBounds{std::uint64_t(16) << 20, std::size_t(1) << 16};
inline constexpr TextBounds kTableTextBounds{std::uint64_t(16) << 20, std::size_t(1) << 12};
inline constexpr TextBounds kStreamTextBounds{std::uint64_t(16) << 30, std::size_t(1) << 12};

// The whole of a text file, `what` naming its kind in messages ("a recipe"): a regular file
// whose size is within the cap (checked before reading), with no line above the line cap and no
// NUL byte. Throws npf::Error naming `path` (and the line, for a line too long or a NUL).
std::string read_text_file(const std::string& path, const std::string& what, const TextBounds& bounds);
// The same from a descriptor open on a regular file (not closed here), read from its start;
// `name` names it in messages. For files opened without following links (owned_folder.h).
std::string read_text_file(int fd, const std::string& name, const std::string& what, const TextBounds& bounds);

// Lines of a text stream, read in blocks: a line without end costs its cap, not the stream.
// `name` is what messages call the stream ("<stdin>", a path); errors are npf::Error naming
// "name:line".
class LineReader {
public:
    // Reads from `fd`, which the reader does not close (standard input: 0).
    LineReader(int fd, std::string name, const TextBounds& bounds);
    // Opens `path` (a regular file, `what` as above, its size within the cap).
    LineReader(const std::string& path, const std::string& what, const TextBounds& bounds);
    ~LineReader();
    LineReader(const LineReader&) = delete;
    LineReader& operator=(const LineReader&) = delete;

    // The next line without its newline ('\r' before it is kept: callers that split on blanks
    // drop it); false at the end of the input.
    bool next(std::string& line);
    // The line next() returned last, from 1.
    std::size_t line_number() const { return m_line; }
    const std::string& name() const { return m_name; }
    // Whether the last line returned ended with a newline.
    bool ended_with_newline() const { return m_last_newline; }

private:
    bool fill();

    int m_fd = -1;
    bool m_owned = false;
    std::string m_name;
    TextBounds m_bounds;
    std::string m_buffer;
    std::size_t m_start = 0;   // the unread part of m_buffer begins here
    std::uint64_t m_total = 0;  // bytes read so far
    std::size_t m_line = 0;
    bool m_eof = false;
    bool m_last_newline = false;
};

}  // namespace npf
