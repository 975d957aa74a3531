// Requests from named fields, as conformance vectors write them:
//   {command: auto_move, form: 2A, fields: {azimuth: "-152.5", elevation: "45.6"}}
// Field names are the layouts' (the names describe_frame prints), values are
// text in the units a person reads: degrees, counts, characters.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "sabus/protocol/catalog.hpp"
#include "sabus/protocol/messages.hpp"

namespace sabus {

// Builds a request of `info`'s command in `form` (a catalog form id; "" for
// commands with one form). The form sets its selector field (jog direction,
// misc sub-command, ...) unless `fields` names it. Fields not named keep their
// defaults. Errors name the field and what its value should look like.
Expected<Request> build_request(const CommandInfo& info, std::string_view form,
                                const std::map<std::string, std::string>& fields);

// The data fields a request of this command and form has, by name.
std::vector<std::string> request_field_names(const CommandInfo& info, std::string_view form);
// Every field name a reply to this command can show: the header, the data
// fields of its reply layout (and of its empty-slot form), ETX and check byte.
std::vector<std::string> reply_field_names(const CommandInfo& info);

}  // namespace sabus
