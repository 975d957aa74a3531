// Files a command names itself (a finding of `sabus fuzz`, a profile of
// `sabus vectors sweep`) in a folder it was given: each is a new file, never
// one that was there, whatever that is (a finding of an earlier run with the
// same seed, a link planted at the name). A file the command was asked to
// write by its name (`sabus record --out`) is not one of these.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace sabus::cli {

// Writes `text` to DIR/STEM.EXT, or to DIR/STEM-2.EXT, -3, ... when that name
// is taken (harness::write_new_file: nothing at a name is opened, followed or
// replaced; whole or not at all), creating DIR first. Its path, or nullopt and
// `error` ("cannot create the folder ...", "... : write failed: No space left
// on device"), with no file left behind.
std::optional<std::filesystem::path> write_new_file(const std::filesystem::path& dir, const std::string& stem,
                                                    const std::string& extension, const std::string& text,
                                                    std::string& error);

}  // namespace sabus::cli
