// The fault and NAK-rule tables (faults.hpp, nak_rules.hpp).
#include "sabus/harness/faults.hpp"
#include "sabus/harness/nak_rules.hpp"

namespace sabus::harness {
namespace {
constexpr FaultInfo kFaults[] = {
#define SABUS_X(id, name, description) {Fault::id, name, description},
    SABUS_FAULTS(SABUS_X)
#undef SABUS_X
};
}  // namespace

std::span<const FaultInfo> all_faults() { return kFaults; }

std::optional<Fault> find_fault(std::string_view name) {
  for (const auto& f : kFaults)
    if (f.name == name) return f.fault;
  return std::nullopt;
}

std::string_view paragraph(NakRule rule) {
  switch (rule) {
#define SABUS_X(id, paragraph, text) \
  case NakRule::id: return paragraph;
    SABUS_NAK_RULES(SABUS_X)
#undef SABUS_X
  }
  return "";
}

std::string_view description(NakRule rule) {
  switch (rule) {
#define SABUS_X(id, paragraph, text) \
  case NakRule::id: return text;
    SABUS_NAK_RULES(SABUS_X)
#undef SABUS_X
  }
  return "";
}

std::string_view name(NakRule rule) {
  switch (rule) {
#define SABUS_X(id, paragraph, text) \
  case NakRule::id: return std::string_view(#id).substr(1);
    SABUS_NAK_RULES(SABUS_X)
#undef SABUS_X
  }
  return "";
}

namespace {
constexpr NakRule kNakRules[] = {
#define SABUS_X(id, paragraph, text) NakRule::id,
    SABUS_NAK_RULES(SABUS_X)
#undef SABUS_X
};
}  // namespace

std::span<const NakRule> all_nak_rules() { return kNakRules; }

std::optional<NakRule> find_nak_rule(std::string_view text) {
  for (NakRule r : kNakRules)
    if (name(r) == text) return r;
  return std::nullopt;
}

}  // namespace sabus::harness
