// Files others read, written whole or not at all. A reader (a person, CI, a
// later run) finds the old file or the new one, never a half-written one;
// no file but the one named is created or replaced (a temporary beside it is
// created exclusively and removed on failure); a failed write is an error
// naming the file, not a file that silently ends early.
#pragma once

#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>

namespace sabus::harness {

// What a file that is not a regular one is, by its st_mode: "a directory",
// "a character device", "a block device", "a FIFO (named pipe)", "a socket";
// "not a regular file" for anything else.
std::string kind_of_file(unsigned mode);

// Writes `text` to `path`, replacing the file there: a new file beside it
// (mkstemp, with the mode a new file gets), flushed to the disk, renamed
// over `path`. A symbolic link is written through (the file it names is
// replaced, the link stays). `path` must be a regular file or not exist;
// false with `error` set otherwise, and when the folder is missing or not
// writable, or the disk is full. On failure the old file is unchanged.
bool replace_file(const std::string& path, std::string_view text, std::string& error);
// The same with the text written by `fill` to a stream (a file too large to
// hold as text: the run JSON made from its journal). `fill` returns false,
// with its own `error`, to leave the old file as it is.
using Fill = std::function<bool(std::ostream& out, std::string& error)>;
bool replace_file(const std::string& path, const Fill& fill, std::string& error);

// Writes `text` to a file that did not exist, and never replaces one: `path`
// itself when no file has that name, else the first free of "STEM-2.EXT",
// "STEM-3.EXT", ... (up to kNewFileTries names). Whole or not at all: the
// text is written and flushed under a temporary name, then linked to the
// name (link() fails on a name taken, however late it was taken). Returns
// the name written, or nullopt with `error` set.
inline constexpr int kNewFileTries = 100;
std::optional<std::string> write_new_file(const std::string& path, std::string_view text, std::string& error);

}  // namespace sabus::harness
