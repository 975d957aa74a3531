// Writing YAML that others read. The vector files sabus writes (recorded
// regression vectors, fuzz findings) are built with yaml-cpp's
// YAML::Emitter, which owns their structure, quoting and escapes. The device
// profile writer (to_yaml) builds its text itself: it runs for every
// requirement a vector is checked against, and the Emitter takes some 30
// times as long (1.7 ms a profile against 53 us); its text values go
// through double_quoted here.
//
// yaml-cpp 0.7 writes a comment's text as it is, splitting lines only at
// '\n': a '\r' in it ends the comment for a YAML reader (the rest of the
// line becomes data), and a control character makes the file invalid
// YAML. In a double-quoted value it escapes control characters but writes
// DEL as it is (yaml-cpp reads it back; YAML 1.2's c-printable excludes it).
// Bytes that are not UTF-8 it replaces with U+FFFD, in both. So text for a
// person to read that comes from outside (a device's reply, a failure
// message, a file name) goes through printable_text, in a comment or in a
// free-text value; data values (matcher texts, names) are written exactly,
// double-quoted.
#pragma once

#include <yaml-cpp/emitter.h>

#include <string>
#include <string_view>

namespace sabus::harness::yaml_writer {

// `text` as a person reads it, and as YAML::Comment can carry it: a line
// for each line of it ('\n' ends a line), each a run of printable
// characters (YAML 1.2 c-printable, nb-char). Everything else is written
// as \xNN for each of its bytes, so a reader still sees what it was:
// control characters (tab and '\r' included), DEL, the C1 controls (U+0085
// NEL among them), the line and paragraph separators U+2028 and U+2029, the
// byte order mark, the noncharacters, and every byte that is not part of
// well-formed UTF-8 (overlong forms, surrogates and code points past
// U+10FFFF included).
std::string printable_text(std::string_view text);

// Comment lines of `text` (printable_text), "# " before each, each ending
// in a newline ("" for ""); written by YAML::Comment. To put before a
// document.
std::string comment_lines(std::string_view text);

// `text` as a YAML double-quoted scalar in printable ASCII: '"' and '\\'
// escaped, every byte outside 0x20-0x7e as \xNN. A YAML reader reads
// printable ASCII back exactly; any other byte comes back as the code point
// of its value (U+0000-U+00FF), so text that is not printable ASCII (which
// no profile text field holds) is changed, but the document stays valid.
std::string double_quoted(std::string_view text);

// The Emitter's text as a file: its output and a final newline. A writer
// that leaves the Emitter in error (a map entry without a value, an
// unbalanced map) is a bug: std::logic_error with the Emitter's reason.
std::string document(const YAML::Emitter& emitter);

}  // namespace sabus::harness::yaml_writer
