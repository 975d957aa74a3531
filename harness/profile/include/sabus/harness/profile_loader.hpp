// Reads device profiles (vectors/profiles/*.yaml). A bad file is rejected
// with file:line:column and the offending key; unknown keys, wrong types,
// values out of range and duplicate keys (which yaml-cpp accepts silently)
// are all errors.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "sabus/harness/profile.hpp"

namespace sabus::harness {

struct ProfileError {
  std::string file;
  int line = 0;      // 1-based; 0 when unknown
  int column = 0;    // 1-based; 0 when unknown
  std::string key;   // dotted path of the offending key, e.g. "axes.az.fast_dps"
  std::string message;
  std::string text() const;  // "file:line:column: key: message"
};

struct ProfileResult {
  std::optional<Profile> profile;
  std::optional<ProfileError> error;
  explicit operator bool() const { return profile.has_value(); }
};

ProfileResult load_profile_file(const std::string& path);
ProfileResult load_profile_text(std::string_view yaml, const std::string& name = "<profile>");

// The default profile, vectors/profiles/rc3000-1.59.yaml in the data
// directory (data_dir.hpp); throws DataDirNotFound when there is none.
std::string default_profile_path();
// Writes a profile back as YAML that load_profile_text reads to an equal profile.
std::string to_yaml(const Profile& profile);
// The same, after a comment of any text (yaml_writer::printable_text: one
// comment line for each line of it, what is not printable as \xNN), which
// leaves the profile read back unchanged.
std::string to_yaml(const Profile& profile, std::string_view comment);

}  // namespace sabus::harness
