// What the value of each reply field rests on (field_classes.hpp).
#include "sabus/protocol/field_classes.hpp"

#include <algorithm>
#include <array>

namespace sabus {
namespace {

using C = FieldClass;
using R = ReplyKind;

// The status block: §3.2 bytes 3-44, which §3.17 repeats in bytes 3-44.
#define SABUS_STATUS_BLOCK(kind, p)                                                                        \
  {kind, "sat name", C::kState, p, "the satellite the controller last moved to, located or stored"},      \
      {kind, "reserved", C::kFixed, p, "40h (byte 13; bytes 45-49 of 31h): \"initialized to 0100 0000b\""}, \
      {kind, "azimuth", C::kMotion, p, "the axis's position"},                                               \
      {kind, "elevation", C::kMotion, p, "the axis's position"},                                             \
      {kind, "polarization", C::kMotion, p, "the axis's position (blank without a feed axis)"},              \
      {kind, "az limits", C::kMotion, p, "the limits the axis is at"},                                       \
      {kind, "el limits", C::kMotion, p, "the limits the axis is at"},                                       \
      {kind, "pol limits", C::kMotion, p, "the limits the axis is at"},                                      \
      {kind, "pol equipment", C::kProfile, p, "the feed the controller is configured with"},                 \
      {kind, "az status", C::kMotion, p, "moving or not, its direction and speed, its alarms"},              \
      {kind, "el status", C::kMotion, p, "moving or not, its direction and speed, its alarms"},              \
      {kind, "pol status", C::kMotion, p, "moving or not, its direction and speed, its alarms"},             \
      {kind, "alarm code", C::kState, p, "the alarm active"},                                                \
      {kind, "track", C::kState, p, "TRACK active, its activity and band"},                                  \
      {kind, "agc", C::kDevice, p, "the signal level measured at the AGC input"},                            \
      {kind, "agc channel", C::kProfile, p, "the AGC input the controller is configured to read"}

constexpr ReplyFieldClass kClasses[] = {
    // §3.1
    {R::kDeviceType, "controller type", C::kFixed, "3.1", "\"3K\" for an RC3000"},
    {R::kDeviceType, "version", C::kProfile, "3.1", "the firmware's version"},
    // §3.2, and the replies of 32h, 33h, 34h and 36h
    SABUS_STATUS_BLOCK(R::kStatus, "3.2"),
    // §3.6
    {R::kQueryName, "index", C::kEcho, "3.6", "the entry asked for"},
    {R::kQueryName, "total", C::kStored, "3.6", "how many names the STORE list holds"},
    {R::kQueryName, "sat name", C::kStored, "3.6", "the STORE list's name at that index"},
    // §3.8: the text of the display and where its cursor is are the
    // controller's user interface, which the spec does not give.
    {R::kDisplay, "row 1", C::kDevice, "3.8", "the display's text"},
    {R::kDisplay, "row 2", C::kDevice, "3.8", "the display's text"},
    {R::kDisplay, "row 3", C::kDevice, "3.8", "the display's text"},
    {R::kDisplay, "row 4", C::kDevice, "3.8", "the display's text"},
    {R::kDisplay, "cursor row", C::kDevice, "3.8", "where the display's user interface put its cursor"},
    {R::kDisplay, "cursor column", C::kDevice, "3.8", "where the display's user interface put its cursor"},
    {R::kDisplay, "cursor status", C::kDevice, "3.8", "whether the display's cursor blinks"},
    // §3.9
    {R::kSignalStrength, "online", C::kState, "3.9", "'0' while remote control is on line"},
    // §3.11
    {R::kSatelliteData, "index", C::kEcho, "3.11", "the preset slot asked for"},
    {R::kSatelliteData, "sat name", C::kStored, "3.11", "the preset's record"},
    {R::kSatelliteData, "longitude", C::kStored, "3.11", "the preset's record"},
    {R::kSatelliteData, "inclination", C::kStored, "3.11", "the preset's record"},
    {R::kSatelliteData, "band", C::kStored, "3.11", "the preset's record"},
    {R::kSatelliteData, "ephemeris", C::kStored, "3.11", "the preset's record"},
    {R::kSatelliteData, "pol offset", C::kStored, "3.11", "the preset's record"},
    // §3.13
    {R::kTleData, "index", C::kEcho, "3.13", "the TLE slot asked for"},
    {R::kTleData, "tle line 1", C::kStored, "3.13", "the slot's TLE"},
    {R::kTleData, "tle line 2", C::kStored, "3.13", "the slot's TLE"},
    // §3.15
    {R::kIessData, "index", C::kEcho, "3.15", "the slot asked for"},
    // §3.16
    {R::kPulseCount, "azimuth count", C::kMotion, "3.16", "the position in pulse counts"},
    {R::kPulseCount, "elevation count", C::kMotion, "3.16", "the position in pulse counts"},
    // §3.17: the status block, then the mode bytes
    SABUS_STATUS_BLOCK(R::kExtendedStatus, "3.17"),
    {R::kExtendedStatus, "current mode", C::kState, "3.17", "the mode the controller is in"},
    {R::kExtendedStatus, "current state", C::kState, "3.17", "the state within that mode"},
    {R::kExtendedStatus, "last exited mode", C::kState, "3.17", "the mode last left"},
    {R::kExtendedStatus, "exit status", C::kState, "3.17", "how that mode was left"},
    {R::kExtendedStatus, "az hundredths", C::kMotion, "3.17", "the hundredths digit of the position"},
    {R::kExtendedStatus, "el hundredths", C::kMotion, "3.17", "the hundredths digit of the position"},
    {R::kExtendedStatus, "spare", C::kDevice, "3.17", "\"spare bytes\", no content given"},
    // §3.21
    {R::kSignpostData, "index", C::kEcho, "3.21", "the signpost slot asked for"},
    {R::kSignpostData, "longitude", C::kStored, "3.21", "the signpost's record"},
    {R::kSignpostData, "frequency", C::kStored, "3.21", "the signpost's record"},
    {R::kSignpostData, "symbol rate", C::kStored, "3.21", "the signpost's record"},
    {R::kSignpostData, "fec", C::kStored, "3.21", "the signpost's record"},
    {R::kSignpostData, "polarization", C::kStored, "3.21", "the signpost's record"},
    {R::kSignpostData, "id", C::kStored, "3.21", "the signpost's record"},
    {R::kSignpostData, "priority", C::kStored, "3.21", "the signpost's record"},
    {R::kSignpostData, "spare", C::kFixed, "3.21", "\"pad with zeros\""},
    // §3.22
    {R::kNavigationData, "lat/lon source", C::kStored, "3.22", "the navigation data"},
    {R::kNavigationData, "latitude", C::kStored, "3.22", "the navigation data"},
    {R::kNavigationData, "reserved (lat seconds)", C::kFixed, "3.22", "\"set to blanks\""},
    {R::kNavigationData, "longitude", C::kStored, "3.22", "the navigation data"},
    {R::kNavigationData, "reserved (lon seconds)", C::kFixed, "3.22", "\"set to blanks\""},
    {R::kNavigationData, "reserved (altitude)", C::kFixed, "3.22", "\"set to blanks\""},
    {R::kNavigationData, "heading source", C::kStored, "3.22", "the navigation data"},
    {R::kNavigationData, "true heading", C::kStored, "3.22", "the navigation data"},
    {R::kNavigationData, "magvar status", C::kStored, "3.22", "the navigation data"},
    {R::kNavigationData, "magnetic variation", C::kStored, "3.22", "the navigation data"},
    {R::kNavigationData, "reserved (time status)", C::kDevice, "3.22", "\"spare\", no content given"},
    {R::kNavigationData, "reserved (time)", C::kDevice, "3.22", "\"spare\", no content given"},
    {R::kNavigationData, "reserved (date)", C::kDevice, "3.22", "\"spare\", no content given"},
    {R::kNavigationData, "reserved (pitch/roll status)", C::kDevice, "3.22", "\"spare\", no content given"},
    {R::kNavigationData, "reserved (pitch)", C::kDevice, "3.22", "\"spare\", no content given"},
    {R::kNavigationData, "reserved (roll)", C::kDevice, "3.22", "\"spare\", no content given"},
    // §3.24
    {R::kJogPosition, "axis", C::kEcho, "3.24", "the axis asked for"},
    {R::kJogPosition, "position", C::kMotion, "3.24", "the axis's position"},
};

#undef SABUS_STATUS_BLOCK

}  // namespace

std::string_view to_string(FieldClass c) {
  switch (c) {
    case FieldClass::kFixed: return "fixed";
    case FieldClass::kEcho: return "echo";
    case FieldClass::kProfile: return "profile";
    case FieldClass::kStored: return "stored";
    case FieldClass::kState: return "state";
    case FieldClass::kMotion: return "motion";
    case FieldClass::kDevice: return "device";
  }
  return "?";
}

std::span<const ReplyFieldClass> reply_field_classes() { return kClasses; }

const ReplyFieldClass* field_class(ReplyKind reply, std::string_view field) {
  const auto it = std::find_if(std::begin(kClasses), std::end(kClasses),
                               [&](const ReplyFieldClass& c) { return c.reply == reply && c.field == field; });
  return it == std::end(kClasses) ? nullptr : &*it;
}

}  // namespace sabus
