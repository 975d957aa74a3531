// Injected faults: each a realistic firmware bug that a conformance suite must
// catch (after libmodbus's test server that misbehaves on purpose). One
// table: id, name (for --fault), description.
#pragma once

#include <bitset>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace sabus::harness {

#define SABUS_FAULTS(X)                                                                                              \
  X(kLrcSkipsByte0, "lrc-skips-byte0", "reply check bytes XOR from byte 1, leaving out the ACK/NAK")                \
  X(kNakBadCheckByte, "nak-bad-check-byte", "a frame with a bad check byte is NAKed instead of ignored")            \
  X(kAnswersForeignAddress, "answers-foreign-address", "frames for other addresses are executed and answered")      \
  X(kNakWithoutCommand, "nak-without-command", "the NAK reply leaves out the command byte: NAK A ETX LRC")          \
  X(kShortStatus, "short-status", "status replies are 51 bytes: the last reserved byte is missing")                 \
  X(kSilentUnknownCommand, "silent-unknown-command", "unknown command codes are ignored instead of NAKed")          \
  X(kExecutesOverlong, "executes-overlong", "a command with extra data bytes is executed instead of NAKed")        \
  X(kOfflineWithoutF, "offline-without-f", "the offline reply leaves out the 'F': ACK A CC ETX LRC")                \
  X(kWrongNibbleBase, "wrong-nibble-base", "binary status bytes use 0x30 instead of 0x40 as their high bits")       \
  X(kLeftJustifiedPosition, "left-justified-position", "positions in replies are left-justified")                  \
  X(kStoreCountOffByOne, "store-count-off-by-one", "query name reports one satellite more than the STORE list has")  \
  X(kCheckByteStxRestarts, "check-byte-stx-restarts", "a check byte of 02h is taken as a new STX")                  \
  X(kModeEnumOffByOne, "mode-enum-off-by-one", "extended status mode values start at 0x21 instead of 0x20")         \
  X(kIgnoresParity, "ignores-parity", "characters with a parity error are accepted")                                \
  X(kAcceptsControlInBody, "accepts-control-in-body",                                                              \
    "control characters inside a frame are dropped from it, the check byte covering them: the rest is executed")  \
  X(kNoStxStxRestart, "no-stx-stx-restart", "an STX where the address belongs does not restart reception")          \
  X(kReplyAddressZero, "reply-address-0x30", "replies carry address 0x30 instead of the controller's")              \
  X(kExtendedStatus52, "extended-status-52", "the extended status reply is 52 bytes, as the text's count says")    \
  X(kExtendedStatusSpeedBit, "extended-status-speed-bit",                                                           \
    "the extended status reply's azimuth status byte has its speed bit S inverted (31h's is right)")                 \
  X(kAzLimitBitsMissing, "az-limit-bits-missing", "the azimuth limit byte (§3.2 byte 32) never shows a limit")         \
  X(kQueryNameZeroBased, "query-name-zero-based", "query name counts indexes from 0")                               \
  X(kWriteNavKeepsStore, "write-nav-keeps-store", "a valid Write Navigation Data keeps the STORE list")            \
  X(kCircularPolAcked, "circular-pol-acked", "polarization movement is ACKed with a circular feed")                \
  X(kJogIntoLimitAcked, "jog-into-limit-acked", "a jog into an asserted limit is ACKed")                            \
  X(kEmptySlotZeros, "empty-slot-zeros", "an empty preset slot is read back with index \"00\" instead of 7Fh 7Fh")  \
  X(kJogIgnoresDuration, "jog-ignores-duration", "jogs run until stopped, whatever their duration")                \
  X(kSecondAxisJogKeepsFirst, "second-axis-jog-keeps-first", "a jog about a second axis does not end the first")   \
  X(kStatusForcesRemote, "status-forces-remote", "device type and status polls force REMOTE mode (RC2000 behaviour)") \
  X(kUnimplementedAcked, "unimplemented-acked", "38h, 3Dh and 3Eh are ACKed although not implemented")             \
  X(kTleIndexTo20, "tle-index-to-20", "TLE indexes 11-20 are accepted")                                             \
  X(kSignpostsWithoutDvb, "signposts-without-dvb", "signposts are accepted without the DVB receiver option")       \
  X(kStowWithoutCapability, "stow-without-capability", "stow and deploy are ACKed on mounts without them")          \
  X(kDropsReplyByte, "drops-reply-byte", "every reply loses its last data byte")                                  \
  X(kDeviceTypeNoDot, "device-type-no-dot", "the device type reply writes the version as \"159 \"")                \
  X(kRemoteDisabledAnswers, "remote-disabled-answers", "with remote control disabled, commands are executed")        \
  X(kDriveResetKeepsAlarm, "drive-reset-keeps-alarm", "a drive reset ('R') ACKs but leaves the axis alarm active")  \
  X(kMoveStopsShort, "move-stops-short", "auto moves stop 1 degree short of their target")                        \
  X(kNeverShowsRest, "never-shows-rest", "after an auto move has ended, the azimuth status still shows auto move in progress") \
  X(kPulseCountStale, "pulse-count-stale", "pulse counts stay those of the power-on position: they do not follow the mount") \
  X(kPulseCountNoOffset, "pulse-count-no-offset", "pulse counts leave out count_offset: position x counts_per_degree") \
  X(kHundredthsAlwaysZero, "hundredths-always-zero", "extended status bytes 49-50 are '0' on a mount with 0.01 deg feedback") \
  X(kForm2CSignDropped, "form2c-sign-dropped", "auto move form 2C ignores the target's sign: -2.57 moves to 2.57")   \
  X(kTargetSpellingsBoth, "target-spellings-both",                                                               \
    "a negative auto-move target is taken in both of E-45's spellings, '-0050' and '00-50'")                       \
  X(kForm2BMirrored, "form2b-negative-mirrored", "auto move form 2B takes a count below count_offset as as far above it") \
  X(kStopKeyIgnoredInRemote, "stop-key-ignored-in-remote", "the Stop key (36h 'K', 48h) does not stop a remote auto move") \
  X(kXReentersRemote, "x-reenters-remote", "'X' in REMOTE mode enters it again: the state reads INITIALIZING_MODE") \
  /* LOCATE geometry (§3.18, §3.23; ERRATA E-80, E-81) */                                                         \
  X(kLocateIgnoresHeading, "locate-ignores-heading", "LOCATE takes mount azimuth 0.0 as true north, whatever the heading") \
  X(kLocateAzimuthCounterclockwise, "locate-azimuth-counterclockwise",                                            \
    "LOCATE turns the azimuth the wrong way: heading less the true azimuth")                                        \
  X(kLocateNorthernLatitude, "locate-northern-latitude", "LOCATE takes a southern latitude as northern")          \
  X(kLocateEasternLongitude, "locate-eastern-longitude", "LOCATE takes a western site longitude as eastern")      \
  X(kLocateMovesOutOfRange, "locate-moves-out-of-range",                                                         \
    "LOCATE to a satellite outside the axis ranges moves to the limits instead of a range error")               \
  X(kLocateIgnoresStop, "locate-ignores-stop",                                                                 \
    "a LOCATE in motion goes on to its satellite after 33h 'X' or the Stop key, which are ACKed")                \
  X(kLocateWithoutSiteCompletes, "locate-without-site-completes",                                               \
    "a LOCATE lacking the site, heading or magnetic variation ends at once as completed instead of waiting")      \
  X(kLocateStopExitCompleted, "locate-stop-exit-completed",                                                     \
    "a LOCATE stopped before it arrives exits with LOCATE_FUNCTION_COMPLETED")                                  \
  X(kLocateStopExitStale, "locate-stop-exit-stale",                                                              \
    "a LOCATE stopped before it arrives never updates the extended status exit status (byte 48): it keeps the last one") \
  X(kStowIgnoresStop, "stow-ignores-stop",                                                                     \
    "a STOW in motion goes on to its stow position after 33h 'X' or the Stop key, which are ACKed")              \
  X(kStowStopExitFinished, "stow-stop-exit-finished",                                                           \
    "a STOW stopped before it arrives exits with STOW_FINISHED_NORMALLY")                                        \
  X(kDeployIgnoresStop, "deploy-ignores-stop",                                                                 \
    "a DEPLOY in motion goes on to its deploy position after 33h 'X' or the Stop key, which are ACKed")          \
  X(kDeployStopExitFinished, "deploy-stop-exit-finished",                                                       \
    "a DEPLOY stopped before it arrives exits with DEPLOY_FINISHED_NORMALLY")                                    \
  X(kSearchIgnoresStop, "search-ignores-stop",                                                                 \
    "a spiral search goes on searching after 33h 'X' or the Stop key, which are ACKed")                          \
  X(kSearchStopExitNoPeak, "search-stop-exit-no-peak",                                                         \
    "a spiral search stopped before it ends exits with SPIRAL_NO_PEAK_FOUND")                                   \
  /* Stored records read back (§3.6, §3.11, §3.13, §3.21) */                                                      \
  X(kSlotReadShiftedInMiddle, "slot-read-shifted-in-middle",                                                     \
    "a read of a slot between the first and the last of its list (3Ah, 3Ch, 44h) answers the next slot's record") \
  X(kStoreEntryShiftedInMiddle, "store-entry-shifted-in-middle",                                                 \
    "35h answers an entry between the first and the last of the STORE list with the next entry's name")          \
  /* Values on every legal profile (issue 32) */                                                                   \
  X(kDeviceTypeFixedVersion, "device-type-fixed-version",                                                        \
    "the device type reply reports version 1.59 whatever the controller's firmware (§3.1)")                        \
  X(kStoresIntoFirstSlot, "stores-into-first-slot",                                                              \
    "39h, 3Bh and 43h store every record into slot 1, whatever index they carry (§3.10, §3.12, §3.20)")          \
  X(kStowLimitBitsMissing, "stow-limit-bits-missing",                                                            \
    "status bytes 32-34 never show a stow limit (bit C, §3.2), also at the stow position after a STOW")           \
  X(kNaksForeignFrames, "naks-foreign-frames",                                                                   \
    "a frame for another address that the controller would NAK (unknown code, wrong length, bad data) is NAKed")  \
  X(kSpareBytesBlank, "spare-bytes-blank",                                                                       \
    "44h returns the signpost's spare bytes 30-33 as blanks instead of the zeros §3.21 fixes")                  \
  X(kAlarmCodeLowBattery, "alarm-code-low-battery",                                                             \
    "status byte 39 shows alarm code 1 (Low Battery) where no alarm is active (§3.2 \"0 No alarm active\")")        \
  X(kExtendedStatusTrackInactive, "extended-status-track-inactive",                                              \
    "the extended status reply's track byte shows SSSS 0000 (not active) while TRACK is active (31h's is right)") \
  /* The line (issue 34) */                                                                                        \
  X(kGarblesReplies, "garbles-replies",                                                                          \
    "every third reply leaves with a wrong check byte, though every byte's parity is right (§4 a garbled reply)")

enum class Fault : std::uint8_t {
#define SABUS_X(id, name, description) id,
  SABUS_FAULTS(SABUS_X)
#undef SABUS_X
  kCount
};

struct FaultInfo {
  Fault fault;
  std::string_view name;
  std::string_view description;
};

std::span<const FaultInfo> all_faults();
std::optional<Fault> find_fault(std::string_view name);

class FaultSet {
 public:
  FaultSet() = default;
  FaultSet(std::initializer_list<Fault> faults) {
    for (auto f : faults) set(f);
  }
  void set(Fault f) { bits_.set(static_cast<std::size_t>(f)); }
  bool has(Fault f) const { return bits_.test(static_cast<std::size_t>(f)); }
  bool any() const { return bits_.any(); }

 private:
  std::bitset<static_cast<std::size_t>(Fault::kCount)> bits_;
};

}  // namespace sabus::harness
