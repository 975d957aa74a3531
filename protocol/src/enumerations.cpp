// Extended status reply enumeration lists: spec §3.17 (40h Extended Device
// Status Poll), section "EXTENDEND STATUS REPLY ENUMERATION LISTS" of the
// RC3000 Appendix REM (rev. 6 May 2008, software 1.59).
//
// The spec prints each list as a C enum whose first 32 names (values 0-1Fh)
// are placeholders ("U0..U31", "00..031", "M0..M31", "A0..A31", ...) that
// are never sent. The placeholders are left out here, so kXxx[i] has the value
// 0x20 + i. Every enum printed in the spec has exactly 32 placeholders (checked
// against the text), and the trailing LAST_xxx / UNDEFINED_MODE sentinel is
// kept because it is part of the printed enum.
//
// Transcription rules (READING-NOTES 27, protocol/ERRATA.md):
//  * OCR turned some underscores into spaces ("LOCATE MODE", "TRACK MANUAL
//    SEARCH ACTIVE"); each such name is one identifier with underscores.
//  * The spec's own spelling is kept exactly (INIT_WAIITNING_..., STOW_WAITITNG_...,
//    DEPLOY_INITIAIZING_MODE, ..._INITATE_MVOEMENT, STOW_..._MODE_CHANGE, ...):
//    these are the spec's names, not ours to correct.
//  * Nothing is reordered: where the print looks displaced (track_states, see
//    below) the printed order is kept and the point is recorded as an erratum.
//
// Everything here is constexpr: no mutable state, no heap allocation.

#include "sabus/protocol/enumerations.hpp"

#include <array>
#include <cstddef>
#include <iterator>

namespace sabus::enums {

namespace {

// ---------------------------------------------------------------------------
// The lists, in the order the spec prints them (the mode list, kModeNames,
// is in the header).
// ---------------------------------------------------------------------------

constexpr std::string_view kSimpleModeStates[] = {
    "INITIALIZING_MODE",
    "WAITING_FOR_USER_INPUT",
    "LAST_SIMPLE_MODE_STATE",
};

constexpr std::string_view kSimpleExitStatus[] = {
    "MODE_NORMAL_EXIT",
    "LAST_SIMPLE_EXIT_CONDITION",
};

constexpr std::string_view kLocateStates[] = {
    "ENTERING_LOCATE_MODE",
    "INITIALIZING_LOCATE_MODE",
    "LOCATE_BEGINNING_ANTENNA_DEPLOYMENT",
    "LOCATE_ANTENNA_DEPLOYMENT_OPENING_FAIRING",  // SWD only
    "LOCATE_ANTENNA_DEPLOYMENT_ELEV_MOVE",
    "LOCATE_ANTENNA_DEPLOYMENT_AZIM_MOVE",
    "LOCATE_UPDATING_DISPLAY",
    "LOCATE_CALCULATE_MAGVAR_FOR_CALCULATE_MODE",  // VSFX only
    "LOCATE_CALCULATING_MAGNETIC_VARIATION",
    "LOCATE_SYNCHRONIZING_SYSTEM_CLOCK_TO_UTC",
    "LOCATE_WAITING_FOR_LAT_LON",
    "LOCATE_WAITING_FOR_HEADING",
    "LOCATE_WAITING_FOR_SAT_DATA",
    "LOCATE_UNDEFINED_PARAMETER_ERROR",
    "LOCATE_READY_TO_LOCATE",
    "LOCATE_AZIMUTH_RANGE_ERROR",
    "LOCATE_ELEVATION_RANGE_ERROR",
    "LOCATE_PERFORMING_MANUAL_SAT_DATA_ENTRY",
    "LOCATE_PERFORMING_PRESET_SAT_DATA_ENTRY",
    "LOCATE_PERFORMING_SATLIST_DATA_ENTRY",
    "LOCATE_WAITING_FOR_POLARIZATION_SELECTION",
    "LOCATE_WAITING_FOR_CONFIRMATION_TO_CONTINUE",
    "LOCATE_PITCH_CALCULATION_FIRST_ELEV_MOVEMENT",   // Ephemeris Tracking
    "LOCATE_PITCH_CALCULATION_AZIM_MOVEMENT",         // Ephemeris Tracking
    "LOCATE_PITCH_CALCULATION_SECOND_ELEV_MOVEMENT",  // Ephemeris Tracking
    "LOCATE_CALCULATING_PITCH",
    "LOCATE_ROLL_CALCULATION_AZIM_MOVEMENT",          // Ephemeris Tracking
    "LOCATE_ROLL_CALCULATION_ELEV_MOVEMENT",          // Ephemeris Tracking
    "LOCATE_CALCULATING_ROLL",                        // Ephemeris Tracking
    "LOCATE_CALCULATE_NORAD_ELEV_ANGLE",              // Ephemeris Tracking
    "LOCATE_CALCULATE_NORAD_AZIM_ANGLE",              // Ephemeris Tracking
    "LOCATE_FIRST_ELEV_MOVEMENT",
    "LOCATE_POL_MOVEMENT",
    "LOCATE_AZIM_MOVEMENT",
    "LOCATE_SECOND_ELEV_MOVEMENT",
    "LOCATE_BEGINNING_SCAN",
    "LOCATE_MOVING_TO_INITIAL_AZIMUTH_SCAN_POSITION",
    "LOCATE_MOVING_TO_INITIAL_ELEVATION_SCAN_POSITION",
    "LOCATE_PERFORMING_SMOOTH_AZIMUTH_SCAN",
    "LOCATE_ADJUST_ELEV_DURING_SMOOTH_AZIMUTH_SCAN",
    "LOCATE_AZIMUTH_STEP_SCAN",
    "LOCATE_ADJUST_ELEVATION_DURING_AZIMUTH_STEP_SCAN",
    "LOCATE_MOVING_TO_SCAN_PEAK",
    "LOCATE_NO_PEAK_FOUND_MOVING_TO_NOMINAL_AZIMUTH",
    "LOCATE_SCAN_FINAL_ELEVATION_ADJUSTMENT",
    "LOCATE_SCAN_WAITING_FOR_EXIT_COMMAND_AFTER_NO_PEAK_FOUND",
    "BEGINNING_SPIRAL_SEARCH",
    "SPIRAL_MOVING_TO_NOMINAL_AZIMUTH_STARTING_POSITION",
    "SPIRAL_SEARCH_STEPPING_CW_IN_AZIMUTH",
    "SPIRAL_SEARCH_ADJUSTING_ELEV_CW_AZIMUTH_STEP",
    "SPIRAL_SEARCH_SAMPLING_SIGNAL_AZ_CW_STEP",
    "SPIRAL_SEARCH_ADJUSTING_AZIMUTH_DURING_UP_ELEVATION_STEP",
    "SPIRAL_SEARCH_STEPPING_UP_IN_ELEVATION",
    "SPIRAL_SEARCH_SAMPLING_SIGNAL_EL_UP_STEP",
    "SPIRAL_SEARCH_STEPPING_CCW_IN_AZIMUTH",
    "SPIRAL_SEARCH_ADJUSTING_ELEV_CCW_AZIMUTH_STEP",
    "SPIRAL_SEARCH_SAMPLING_SIGNAL_AZ_CCW_STEP",
    "SPIRAL_SEARCH_ADJUSTING_AZIMUTH_DURING_DOWN_ELEVATION_STEP",
    "SPIRAL_SEARCH_STEPPING_DOWN_IN_ELEVATION",
    "SPIRAL_SEARCH_SAMPLING_SIGNAL_EL_DOWN_STEP",
    "SPIRAL_SEARCH_NO_PEAK_MOVING_TO_AZIMUTH",
    "SPIRAL_SEARCH_NO_PEAK_MOVING_TO_ELEVATION",
    "LAST_LOCATE_STATE",
};

// The entry lost at a page break (READING-NOTES 28): every movement has a
// STOP_KEY / MODE_CHANGED pair except the pitch-calculation second elevation
// movement, whose MODE_CHANGED partner is missing from the print.
constexpr std::string_view kLostLocateExit =
    "LOCATE_PITCH_CALC_SECOND_ELEV_MOVEMENT_MODE_CHANGED";

// locate_exit_conditions with the lost entry restored (the default reading).
constexpr std::string_view kLocateExitRestored[] = {
    "LOCATE_CANNOT_INITIATE_MOVEMENT_BELOW_DOWN_LIMIT",  // CPS only
    "LOCATE_ANTENNA_DEPLOYMENT_FAIRING_NOT_CLEAR",       // SWD only
    "LOCATE_ANTENNA_DEPLOYMENT_ELEV_MOVE_STOP_KEY",
    "LOCATE_ANTENNA_DEPLOYMENT_ELEV_MOVE_MODE_CHANGED",
    "LOCATE_ANTENNA_DEPLOYMENT_AZIM_MOVE_STOP_KEY",
    "LOCATE_ANTENNA_DEPLOYMENT_AZIM_MOVE_MODE_CHANGED",
    "LOCATE_PITCH_CALC_FIRST_ELEV_MOVEMENT_STOP_KEY",
    "LOCATE_PITCH_CALC_FIRST_ELEV_MOVEMENT_MODE_CHANGED",
    "LOCATE_PITCH_CALC_AZIM_MOVEMENT_STOP_KEY",
    "LOCATE_PITCH_CALC_AZIM_MOVEMENT_MODE_CHANGED",
    "LOCATE_PITCH_CALC_SECOND_ELEV_MOVEMENT_STOP_KEY",     // 0x2A
    kLostLocateExit,                                       // 0x2B, not printed
    "LOCATE_ROLL_CALC_AZIM_MOVEMENT_STOP_KEY",
    "LOCATE_ROLL_CALC_AZIM_MOVEMENT_MODE_CHANGED",
    "LOCATE_ROLL_CALC_ELEV_MOVEMENT_STOP_KEY",
    "LOCATE_ROLL_CALC_ELEV_MOVEMENT_MODE_CHANGED",
    "LOCATE_FIRST_ELEV_MOVEMENT_STOP_KEY",
    "LOCATE_FIRST_ELEV_MOVEMENT_MODE_CHANGED",  // printed inside a "$\texttt{...}$" artifact
    "LOCATE_POL_MOVEMENT_STOP_KEY",
    "LOCATE_POL_MOVEMENT_MODE_CHANGED",
    "LOCATE_AZIM_MOVEMENT_STOP_KEY",
    "LOCATE_AZIM_MOVEMENT_MODE_CHANGED",
    "LOCATE_SECOND_ELEV_MOVEMENT_STOP_KEY",
    "LOCATE_SECOND_ELEV_MOVEMENT_MODE_CHANGED",
    "LOCATE_FUNCTION_COMPLETED",  // 0x38 restored, 0x37 as printed
    "LOCATE_INITIAL_AZIMUTH_SCAN_POSITION_STOP_KEY",
    "LOCATE_INITIAL_AZIMUTH_SCAN_POSITION_MODE_CHANGED",
    "LOCATE_INITIAL_ELEVATION_SCAN_POSITION_STOP_KEY",
    "LOCATE_INITIAL_ELEVATION_SCAN_POSITION_MODE_CHANGED",
    "LOCATE_ADJUST_ELEV_SMOOTH_AZIMUTH_SCAN_STOP_KEY",
    "LOCATE_ADJUST_ELEV_SMOOTH_AZIMUTH_SCAN_MODE_CHANGED",
    "LOCATE_AZIMUTH_STEP_SCAN_STOP_KEY",
    "LOCATE_AZIMUTH_STEP_SCAN_MODE_CHANGED",
    "LOCATE_ADJUST_ELEV_AZIMUTH_STEP_SCAN_STOP_KEY",
    "LOCATE_ADJUST_ELEV_AZIMUTH_STEP_SCAN_MODE_CHANGED",
    "LOCATE_SCAN_FINAL_AZIMUTH_MOVE_STOP_KEY",
    "LOCATE_SCAN_FINAL_AZIMUTH_MOVE_MODE_CHANGED",
    "LOCATE_SCAN_FINAL_ELEVATION_ADJUSTMENT_STOP_KEY",
    "LOCATE_SCAN_FINAL_ELEVATION_ADJUSTMENT_MODE_CHANGED",
    "LOCATE_FINISHING_WITH_NO_PEAK_FOUND",
    "SPIRAL_MOVING_TO_AZIM_STARTING_STOP_KEY",
    "SPIRAL_MOVING_TO_AZIM_STARTING_MODE_CHANGED",
    "SPIRAL_STEPPING_CW_IN_AZIMUTH_STOP_KEY",
    "SPIRAL_STEPPING_CW_IN_AZIMUTH_MODE_CHANGED",
    "SPIRAL_ADJUSTING_ELEV_CW_AZIMUTH_STEP_STOP_KEY",
    "SPIRAL_ADJUSTING_ELEV_CW_AZIMUTH_STEP_MODE_CHANGED",
    "SPIRAL_ADJUSTING_AZIM_UP_ELEV_STEP_STOP_KEY",
    "SPIRAL_ADJUSTING_AZIM_UP_ELEV_STEP_MODE_CHANGED",
    "SPIRAL_STEPPING_UP_IN_ELEVATION_STOP_KEY",
    "SPIRAL_STEPPING_UP_IN_ELEVATION_MODE_CHANGED",
    "SPIRAL_STEPPING_CCW_IN_AZIMUTH_STOP_KEY",
    "SPIRAL_STEPPING_CCW_IN_AZIMUTH_MODE_CHANGED",
    "SPIRAL_ADJUSTING_ELEV_CCW_AZIMUTH_STEP_STOP_KEY",
    "SPIRAL_ADJUSTING_ELEV_CCW_AZIMUTH_STEP_MODE_CHANGED",
    "SPIRAL_ADJUSTING_AZIM_DOWN_ELEVATION_STEP_STOP_KEY",
    // Printed "SPIRAL ADJUSTING AZIM ELEVATION STEP MODE CHANGED": the DOWN of
    // its STOP_KEY partner is not in the print. Kept as printed (the name is
    // still unique, and no value depends on it).
    "SPIRAL_ADJUSTING_AZIM_ELEVATION_STEP_MODE_CHANGED",
    "SPIRAL_STEPPING_DOWN_IN_ELEVATION_STOP_KEY",
    "SPIRAL_STEPPING_DOWN_IN_ELEVATION_MODE_CHANGED",
    "SPIRAL_NO_PEAK_MOVING_TO_AZIMUTH_STOP_KEY",
    "SPIRAL_NO_PEAK_MOVING_TO_AZIMUTH_MODE_CHANGED",
    "SPIRAL_NO_PEAK_MOVING_TO_ELEVATION_STOP_KEY",
    "SPIRAL_NO_PEAK_MOVING_TO_ELEVATION_MODE_CHANGED",
    "SPIRAL_NO_PEAK_FOUND",
    "LAST_LOCATE_EXIT_CONDITION",
};

// locate_exit_conditions exactly as printed: the restored table without the
// lost entry, derived at compile time so the two readings cannot drift apart.
template <std::size_t N>
constexpr std::array<std::string_view, N - 1> without_entry(
    const std::string_view (&src)[N], std::string_view drop) {
  std::array<std::string_view, N - 1> out{};
  std::size_t j = 0;
  for (std::size_t i = 0; i < N; ++i) {
    if (src[i] == drop) continue;
    if (j == N - 1) throw "entry to drop not found";  // not a constant expression
    out[j++] = src[i];
  }
  return out;
}

constexpr auto kLocateExitPrinted = without_entry(kLocateExitRestored, kLostLocateExit);

constexpr std::string_view kStoreStates[] = {
    "STORE_ENTERING_MODE",
    "STORE_WAITING_FOR_OVERWRITE_CONFIRMATION",
    "STORE_WAITING_FOR_SAT_DATA_CONFIRMATION",
    "STORE_WAITING_TO_MODE_OUT_DUE_TO_INCORRECT_SAT_DATA",
    "STORE_WAITING_FOR_POLARIZATION_ADJUSTMENT",
    "STORE_CROSS_POL_MOVE",
    "STORE_WAITING_FOR_TRACK_POL_SELECTION",
    "STORE_MOVING_POL_FOR_TRACK",
    "LAST_STORE_STATE",
};

constexpr std::string_view kStoreExit[] = {
    "STORE_INVALID_REGION",  // CPS only
    "STORE_LIST_FULL",
    "STORE_SAT_NAME_ALREADY_STORED",
    "STORE_USER_INDICATES_SAT_DATA_INCORRECT",
    "STORE_CROSS_POL_MOVE_MODE_CHANGED",
    "STORE_USER_MODED_OUT",
    "STORE_SAT_DATA_STORED_OK",
    "STORE_USER_MODED_OUT_AT_TRACK_POL_SELECTION",
    "STORE_USER_MODED_OUT_IN_TRACK_POL_MOVE",
    "STORE_PROCEEDING_TO_TRACK_MODE",
    "LAST_STORE_EXIT_CONDITION",
};

constexpr std::string_view kTrackStates[] = {
    "TRACK_ENTERING_MODE",
    "TRACK_WAITING_FOR_C_OR_KU_SELECTION",
    "TRACK_INITIALIZING_DISPLAY",
    "TRACK_DEPLOYING_ELEVATION_AXIS",
    "TRACK_POSITIONING_POLARIZATION",
    "TRACK_WAITING_FOR_EXIT_CONFIRMATION",  // LNR only
    "TRACK_INITIALIZING_PARAMETERS",
    "TRACK_STEP_PEAKING",
    "TRACK_STEP_WAITING_FOR_SIGNAL_TO_RETURN",
    "TRACK_STEP_IDLE",
    "TRACK_SEARCH_PERFORMING_SEARCH_PATTERN",
    "TRACK_SEARCH_MOVING_TO_FOUND_PEAK",
    "TRACK_SEARCH_WAITING_TO_SEARCH_AGAIN",
    "TRACK_MANUAL_SEARCH_NOMINAL_ELEV_MOVE",
    "TRACK_MANUAL_SEARCH_NOMINAL_AZIM_MOVE",
    "TRACK_MANUAL_SEARCH_ACTIVE",
    "TRACK_MEMORY_IDLE",
    "TRACK_MEMORY_PEAKING",
    "TRACK_MEMORY_REPOSITION",
    "TRACK_ERROR_CREEP_JAMMED",
    "TRACK_ERROR_CREEP_LIMIT",
    "TRACK_ERROR_CREEP_DRIVE",
    "TRACK_ERROR_PEAK_LIMIT",
    "TRACK_ERROR_SCALE_FACTOR",
    "TRACK_ERROR_TRACK_GEO",
    "TRACK_ERROR_TRACK_SYSTEM",
    "TRACK_ERROR_TRACK_CHECKSUM",
    "TRACK_ERROR_UNDEFINED_STATUS",
    "TRACK_MENU_WAITING_FOR_SELECTION",
    "TRACK_MENU_VIEW",
    "TRACK_MENU_MODIFY",
    "TRACK_TLE_IDLE",
    "TRACK_TLE_REPOSITION",
    "TRACK_MANUAL_SEARCH_JOG_AZIM_CCW",
    "TRACK_MANUAL_SEARCH_JOG_AZIM_CW",
    "TRACK_MANUAL_SEARCH_JOG_ELEV_DOWN",
    "TRACK_MANUAL_SEARCH_JOG_ELEV_UP",
    // Printed order kept. JOG_POL_CW is printed after IDLE, set apart by blank
    // lines, which looks like a layout displacement (manual_states orders the
    // same items JOG_POL_CW, JOG_POL_CCW, AUTO_POL_MOVE, IDLE); the text does
    // not say so, so nothing is moved. Recorded as an erratum.
    "TRACK_MANUAL_SEARCH_JOG_POL_CCW",
    "TRACK_MANUAL_SEARCH_AUTO_POL_MOVE",
    "TRACK_MANUAL_SEARCH_IDLE",
    "TRACK_MANUAL_SEARCH_JOG_POL_CW",
    "LAST_TRACK_STATE",
};

// ERRATA E-34's other side: track_states with its last four in the order of
// manual_states (JOG_POL_CW, JOG_POL_CCW, AUTO_POL_MOVE, IDLE), derived from
// the printed table at compile time so that the two cannot drift apart.
template <std::size_t N>
constexpr std::array<std::string_view, N> with_manual_pol_order(const std::string_view (&src)[N]) {
  std::array<std::string_view, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = src[i];
  constexpr std::string_view kOrder[] = {"TRACK_MANUAL_SEARCH_JOG_POL_CW", "TRACK_MANUAL_SEARCH_JOG_POL_CCW",
                                         "TRACK_MANUAL_SEARCH_AUTO_POL_MOVE", "TRACK_MANUAL_SEARCH_IDLE"};
  std::size_t first = N;
  for (std::size_t i = 0; i < N; ++i)
    if (src[i] == "TRACK_MANUAL_SEARCH_JOG_POL_CCW") first = i;
  if (first + 4 >= N) throw "the four pol states not found";  // not a constant expression
  for (std::size_t k = 0; k < 4; ++k) out[first + k] = kOrder[k];
  return out;
}
constexpr auto kTrackStatesManualOrder = with_manual_pol_order(kTrackStates);

constexpr std::string_view kStowStates[] = {
    "STOW_INITIALIZING_MODE",
    "STOW_WAITING_FOR_CONTINUE_CONFIRMATION",
    "STOW_CONTINUING_OPERATION",
    "STOW_MOVING_TO_INITIAL_CW_POSITION",           // SWD only
    "STOW_WAITING_TO_CONFIRM_INVALID_STOW_SWITCH",  // SWD only
    "STOW_MOVING_TO_AZIM_STOW",
    "STOW_SEARCHING_FOR_AZIM_STOW_SWITCH",
    "STOW_WAITITNG_CANNOT_FIND_AZ_STOW_SWITCH",     // spec spelling
    "STOW_MOVING_TO_POL_STOW",
    "STOW_SEARCHING_FOR_POL_STOW_SWITCH",
    "STOW_WAITING_CANNOT_FIND_POL_STOW_SWITCH",
    "STOW_WAITING_OUTSIDE_OF_AZIM_STOW_WINDOW",     // SWD only
    "STOW_MOVING_TO_ELEV_STOW",
    "STOW_CLOSING_FAIRING",                         // SWD only
    "STOW_WAITING_FAIRING_CANT_MOVE_ELEV_NOT_AT_STOW",  // SWD only
    "STOW_WAITING_FAIRING_NOT_AT_STOW",             // SWD only
    "LAST_STOW_STATE",
};

constexpr std::string_view kStowExit[] = {
    "STOW_MODE_OUT_FROM_CONTINUE_CONFIRMATION",
    "STOW_MOVING_TO_INITIAL_CW_POSITION_MOVE_STOPPED",  // SWD only
    "STOW_MOVING_TO_INITIAL_CW_POSITION_MODE_CHANGE",   // SWD only; spec has CHANGE, not CHANGED
    "STOW_INVALID_AZ_STOW_SWITCH",                      // SWD only
    "STOW_MOVING_TO_AZIM_STOW_MOVE_STOPPED",
    "STOW_MOVING_TO_AZIM_STOW_MODE_CHANGED",
    "STOW_SEARCHING_FOR_AZIM_STOW_SWITCH_MOVE_STOPPED",
    "STOW_SEARCHING_FOR_AZIM_STOW_SWITCH_MODE_CHANGED",
    "STOW_CANNOT_FIND_AZ_STOW_SWITCH",
    "STOW_MOVING_TO_POL_STOW_MOVE_STOPPED",
    "STOW_MOVING_TO_POL_STOW_MODE_CHANGED",
    "STOW_SEARCHING_FOR_POL_STOW_SWITCH_MOVE_STOPPED",
    "STOW_SEARCHING_FOR_POL_STOW_SWITCH_MODE_CHANGED",
    "STOW_CANNOT_FIND_POL_STOW_SWITCH",
    "STOW_OUTSIDE_OF_AZIM_STOW_WINDOW",  // SWD only
    // (page break in the print here)
    "STOW_MOVING_TO_ELEV_STOW_MOVE_STOPPED",
    "STOW_MOVING_TO_ELEV_STOW_MODE_CHANGED",
    "STOW_FINISHED_NORMALLY",
    "STOW_FINISHED_WITH_ELEV_NOT_AT_STOW",     // SWD only
    "STOW_FINISHED_WITH_FAIRING_NOT_AT_STOW",  // SWD only
    "LAST_STOW_EXIT_CONDITION",
};

constexpr std::string_view kDeployStates[] = {
    "DEPLOY_INITIAIZING_MODE",  // spec spelling
    "DEPLOY_WAITING_FOR_CONTINUE_CONFIRMATION",
    "DEPLOY_OPENING_FAIRING",            // SWD only
    "DEPLOY_WAITING_FAIRING_NOT_CLEAR",  // SWD only
    "DEPLOY_MOVING_ELEVATION",
    "DEPLOY_MOVING_POL",
    "DEPLOY_MOVING_AZIMUTH",
    "LAST_DEPLOY_STATE",
};

constexpr std::string_view kDeployExit[] = {
    "DEPLOY_MOVING_ELEVATION_MOVE_STOPPED",
    "DEPLOY_MOVING_ELEVATION_MODE_CHANGED",
    "DEPLOY_MOVING_POL_MOVE_STOPPED",
    "DEPLOY_MOVING_POL_MODE_CHANGED",
    "DEPLOY_MOVING_AZIMUTH_MOVE_STOPPED",
    "DEPLOY_MOVING_AZIMUTH_MODE_CHANGED",
    "DEPLOY_FINISHED_NORMALLY",
    "LAST_DEPLOY_EXIT_CONDITION",
};

constexpr std::string_view kMenuStates[] = {
    "MENU_WAITING_FOR_SELECTION",
    "LAST_MENU_STATE",
};

constexpr std::string_view kMenuExit[] = {
    "MENU_MODE_NORMAL_EXIT",
    "LAST_MENU_EXIT_CONDITION",
};

constexpr std::string_view kManualStates[] = {
    "MANUAL_INITIALIZING_MODE",
    "MANUAL_JOG_AZIM_CCW",
    "MANUAL_JOG_AZIM_CW",
    "MANUAL_JOG_ELEV_DOWN",
    "MANUAL_JOG_ELEV_UP",
    "MANUAL_JOG_POL_CW",
    "MANUAL_JOG_POL_CCW",
    "MANUAL_AUTO_POL_MOVE",
    "MANUAL_IDLE",  // 0x28
    "LAST_MANUAL_STATE",
};

constexpr std::string_view kPosConfirmStates[] = {
    "POS_CONFIRM_INITIALIZING_MODE",
    "POS_CONFIRM_WAITING_FOR_SAVE_OR_CLEAR_DECISION",
    "LAST_POS_CONFIRM_STATE",
};

constexpr std::string_view kFairingStates[] = {
    "FAIRING_WAITING_ELEV_NOT_STOWED",
    "FAIRING_WAITING_FOR_USER_INPUT",
    "FAIRING_OPENING_TO_CLEAR",
    "FAIRING_OPENING_TO_SERVICE",
    "FAIRING_CLOSING_TO_STOW",
    "FAIRING_CLOSING_TO_CLEAR",
    "FAIRING_OPENING",
    "FAIRING_CLOSING",
    "LAST_FAIRING_STATE",
};

constexpr std::string_view kTruckPosStates[] = {
    "TRUCK_POS_INITIALIZING_MODE",
    "TRUCK_POS_WAITING_FOR_MANUAL_PRESET_GPS_SELECTION",
    "TRUCK_POS_CALCULATING_MAGVAR",  // LNR only
    "TRUCK_POS_MANUAL_LAT_ENTRY",
    "TRUCK_POS_MANUAL_LON_ENTRY",
    "TRUCK_POS_WAITING_FOR_PRESET_ENTRY",
    "TRUCK_POS_WAITING_FOR_GPS_ENTRY",
    "LAST_TRUCK_POS_STATE",
};

constexpr std::string_view kInitStates[] = {
    "INIT_INITIALIZING_MODE",
    "INIT_WAIITNING_FOR_DEPLOY_CONFIRMATION",  // spec spelling
    "INIT_OPENING_FAIRING",                        // SWD only
    "INIT_FAIRING_NOT_CLEAR_WAITING_TO_MODE_OUT",  // SWD only
    "INIT_MOVING_ELEV_TO_DEPLOY",
    "INIT_MOVING_AZIM_TO_DEPLOY",
    "INIT_GETTING_LAT_LON_FROM_GPS",
    "INIT_SYNCHRONIZING_TIME_TO_UTC",
    "INIT_GETTING_HEADING_FROM_COMPASS",
    "INIT_CALCULATING_MAGVAR",
    "LAST_INIT_STATE",
};

constexpr std::string_view kInitExit[] = {
    "INIT_MOVING_ELEV_TO_DEPLOY_MOVE_STOPPED",
    "INIT_MOVING_ELEV_TO_DEPLOY_MODE_CHANGED",
    "INIT_MOVING_AZIM_TO_DEPLOY_MOVE_STOPPED",
    "INIT_MOVING_AZIM_TO_DEPLOY_MODE_CHANGED",
    "INIT_NORMAL_EXIT",
    "LAST_INIT_EXIT_CONDITION",
};

constexpr std::string_view kSetupPackStates[] = {
    "SETUP_PACK_WAITING_FOR_USER_TO_INITATE_MVOEMENT",  // spec spelling
    "SETUP_PACK_RETRACTING_AZIM",
    "SETUP_PACK_EXTENDING_AZIM",
    "SETUP_PACK_RETRACTING_ELEV",
    "SETUP_PACK_EXTENDING_ELEV",
    "SETUP_PACK_WAITING_FOR_CONFIRMATION_OF_ENDING_POSITION",
    "LAST_SETUP_PACK_STATE",
};

constexpr std::string_view kSetupPackExit[] = {
    "SETUP_PACK_RETRACTING_AZIM_MOVE_STOPPED",
    "SETUP_PACK_RETRACTING_AZIM_MODE_CHANGED",
    "SETUP_PACK_EXTENDING_AZIM_MOVE_STOPPED",
    "SETUP_PACK_EXTENDING_AZIM_MODE_CHANGED",
    "SETUP_PACK_RETRACTING_ELEV_MOVE_STOPPED",
    "SETUP_PACK_RETRACTING_ELEV_MODE_CHANGED",
    "SETUP_PACK_EXTENDING_ELEV_MOVE_STOPPED",
    "SETUP_PACK_EXTENDING_ELEV_MODE_CHANGED",
    "SETUP_PACK_NORMAL_EXIT",
    "LAST_SETUP_PACK_EXIT_CONDITION",
};

constexpr std::string_view kRecallStates[] = {
    "RECALL_ENTERING_MODE",
    "RECALL_NO_SATS_STORED_WAITING_TO_EXIT",
    "RECALL_WAITING_FOR_USER_TO_SCROLL_THROUGH_LIST",
    "RECALL_WAITING_FOR_INVALID_DATA_ACKNOWLEDGEMENT",
    "RECALL_WAITING_FOR_INITIAL_POLARIZATION_SELECTION",
    "RECALL_PERFORMING_ELEVATION_MOVE",
    "RECALL_PERFORMING_POLARIZATION_MOVE",
    "RECALL_PERFORMING_AZIMUTH_MOVE",
    "LAST_RECALL_STATE",
};

constexpr std::string_view kRecallExit[] = {
    "RECALL_ELEV_MOVE_STOPPED",
    "RECALL_ELEV_MOVE_MODE_CHANGED",
    "RECALL_POL_MOVE_STOPPED",
    "RECALL_POL_MOVE_MODE_CHANGED",
    "RECALL_AZIM_MOVE_STOPPED",
    "RECALL_AZIM_MOVE_MODE_CHANGED",
    "RECALL_SWITCHING_TO_TRACK_MODE",
    "RECALL_NORMAL_EXIT",  // 0x27
    "LAST_RECALL_EXIT_CONDITION",
};

// ---------------------------------------------------------------------------
// The EnumList objects.
// ---------------------------------------------------------------------------

constexpr EnumList kModeList{"mode_names", kModeNames};
constexpr EnumList kSimpleModeStatesList{"simple_mode_states", kSimpleModeStates};
constexpr EnumList kSimpleExitList{"simple_exit_status", kSimpleExitStatus};
constexpr EnumList kLocateStatesList{"locate_states", kLocateStates};
constexpr EnumList kLocateExitRestoredList{"locate_exit_conditions", kLocateExitRestored};
constexpr EnumList kLocateExitPrintedList{"locate_exit_conditions", kLocateExitPrinted};
constexpr EnumList kStoreStatesList{"store_states", kStoreStates};
constexpr EnumList kStoreExitList{"store_exit_conditions", kStoreExit};
constexpr EnumList kTrackStatesList{"track_states", kTrackStates};
constexpr EnumList kTrackStatesManualOrderList{"track_states", kTrackStatesManualOrder};
constexpr EnumList kStowStatesList{"stow_states", kStowStates};
constexpr EnumList kStowExitList{"stow_exit_conditions", kStowExit};
constexpr EnumList kDeployStatesList{"deploy_states", kDeployStates};
constexpr EnumList kDeployExitList{"deploy_exit_conditions", kDeployExit};
constexpr EnumList kMenuStatesList{"menu_states", kMenuStates};
constexpr EnumList kMenuExitList{"menu_exit_conditions", kMenuExit};
constexpr EnumList kManualStatesList{"manual_states", kManualStates};
constexpr EnumList kPosConfirmStatesList{"pos_confirm_states", kPosConfirmStates};
constexpr EnumList kFairingStatesList{"fairing_mode_states", kFairingStates};
constexpr EnumList kTruckPosStatesList{"truck_pos_mode_states", kTruckPosStates};
constexpr EnumList kInitStatesList{"init_mode_states", kInitStates};
constexpr EnumList kInitExitList{"init_exit_conditions", kInitExit};
constexpr EnumList kSetupPackStatesList{"setup_pack_mode_states", kSetupPackStates};
constexpr EnumList kSetupPackExitList{"setup_pack_exit_conditions", kSetupPackExit};
constexpr EnumList kRecallStatesList{"recall_mode_states", kRecallStates};
constexpr EnumList kRecallExitList{"recall_exit_conditions", kRecallExit};

// Every list, mode list first, then in the order the spec prints them; the
// tables differ only in which locate_exit_conditions (E-28) and which
// track_states (E-34) they hold.
constexpr auto all_lists_with(const EnumList* locate_exit, const EnumList* track_states) {
  return std::array<const EnumList*, 24>{
      &kModeList,          &kSimpleModeStatesList, &kSimpleExitList,
      &kLocateStatesList,  locate_exit,            &kStoreStatesList,
      &kStoreExitList,     track_states,           &kStowStatesList,
      &kStowExitList,      &kDeployStatesList,     &kDeployExitList,
      &kMenuStatesList,    &kMenuExitList,         &kManualStatesList,
      &kPosConfirmStatesList, &kFairingStatesList, &kTruckPosStatesList,
      &kInitStatesList,    &kInitExitList,         &kSetupPackStatesList,
      &kSetupPackExitList, &kRecallStatesList,     &kRecallExitList,
  };
}
constexpr auto kAllRestored = all_lists_with(&kLocateExitRestoredList, &kTrackStatesList);
constexpr auto kAllPrinted = all_lists_with(&kLocateExitPrintedList, &kTrackStatesList);
constexpr auto kAllRestoredManualOrder = all_lists_with(&kLocateExitRestoredList, &kTrackStatesManualOrderList);
constexpr auto kAllPrintedManualOrder = all_lists_with(&kLocateExitPrintedList, &kTrackStatesManualOrderList);

// ---------------------------------------------------------------------------
// Compile-time checks of the values the rest of the project relies on.
// ---------------------------------------------------------------------------

static_assert(value_in(kModeNames, "MANUAL_MODE") == 0x20);
static_assert(value_in(kModeNames, "AUTO_MODE") == 0x21);
static_assert(value_in(kModeNames, "SPIRAL_REMOTE_MODE") == 0x26);
static_assert(value_in(kModeNames, "STORE_SAT_MODE") == 0x27);
static_assert(value_in(kModeNames, "REMOTE_MODE") == 0x32);
static_assert(value_in(kLocateExitRestored, "LOCATE_FUNCTION_COMPLETED") == 0x38);
static_assert(value_in(kLocateExitPrinted, "LOCATE_FUNCTION_COMPLETED") == 0x37);
static_assert(kLocateExitPrinted.size() + 1 == std::size(kLocateExitRestored));
static_assert(value_in(kTrackStates, "TRACK_MANUAL_SEARCH_JOG_POL_CW") == 0x48);
static_assert(value_in(kTrackStatesManualOrder, "TRACK_MANUAL_SEARCH_JOG_POL_CW") == 0x45);
static_assert(value_in(kTrackStatesManualOrder, "TRACK_MANUAL_SEARCH_IDLE") == 0x48);
static_assert(value_in(kTrackStatesManualOrder, "LAST_TRACK_STATE") == value_in(kTrackStates, "LAST_TRACK_STATE"));

// Every value of every list is a printable data byte, 0x20..0x7F.
constexpr bool all_lists_fit() {
  for (const EnumList* list : kAllRestored)
    if (list->names.size() > 0x80 - kFirstValue) return false;
  return true;
}
static_assert(all_lists_fit());

// ---------------------------------------------------------------------------
// Mode -> (state list, exit list), from the "used for" / "uses" comments of
// §3.17. Built at compile time; an unknown mode name fails to compile.
// ---------------------------------------------------------------------------

struct Assignment {
  const EnumList* states = nullptr;
  const EnumList* exits = nullptr;
};

constexpr auto build_assignments() {
  std::array<Assignment, std::size(kModeNames)> a{};
  auto set = [&a](std::string_view mode, const EnumList* states, const EnumList* exits) {
    Assignment& slot = a[index_in(kModeNames, mode)];
    if (slot.states != nullptr || slot.exits != nullptr) throw "mode assigned twice";
    slot = {states, exits};
  };

  // simple_mode_states: "used for: POSITION_MODE, AUX_MODE, HEADING_FIX_MODE,
  // SETTINGS_MODE, DEFINE_MODE TRUCK_HDG_MODE, REMOTE_MODE, RESET_MODE,
  // DELETE_MODE, all 11 configuration modes". simple_exit_status goes with it.
  // (The print lacks the comma after DEFINE_MODE: both modes are meant.)
  for (std::string_view m : {"POSITION_MODE", "AUX_MODE", "HEADING_FIX_MODE", "SETTINGS_MODE",
                             "DEFINE_MODE", "TRUCK_HDG_MODE", "REMOTE_MODE", "RESET_MODE",
                             "DELETE_MODE"})
    set(m, &kSimpleModeStatesList, &kSimpleExitList);

  // "all 11 configuration modes": the mode list holds 20 modes after
  // "START OF PROGRAMMING MODES" (CONFIG_MENU_MODE .. TLE_2_CONFIG_MODE), and
  // the text does not say which 11 are meant. Decision: CONFIG_MENU_MODE is a
  // menu and takes the menu lists (below); the 19 modes after it, from
  // ANTENNA_CONFIG_MODE to TLE_2_CONFIG_MODE (PULSE_LIMITS_MODE included, it
  // sits inside that block), all take the simple lists. Giving them a list
  // rather than none is the reading that lets a decoder name their values.
  for (std::size_t i = index_in(kModeNames, "ANTENNA_CONFIG_MODE");
       i <= index_in(kModeNames, "TLE_2_CONFIG_MODE"); ++i)
    set(kModeNames[i], &kSimpleModeStatesList, &kSimpleExitList);

  // menu_states / menu_exit_conditions carry no "used for" comment. The only
  // menu modes are CONFIG_MENU_MODE and DIAG_MENU_MODE; DIAG_MENU_MODE belongs
  // to the maintenance block, and "no maintenance modes are instrumented", so
  // the menu lists go to CONFIG_MENU_MODE only.
  set("CONFIG_MENU_MODE", &kMenuStatesList, &kMenuExitList);

  // The locate lists are for LOCATE_MODE. They also hold the spiral search
  // (BEGINNING_SPIRAL_SEARCH, SPIRAL_SEARCH_* states, SPIRAL_* exits, ending
  // in SPIRAL_NO_PEAK_FOUND) and no separate spiral list is printed, so a
  // remotely commanded spiral search (SPIRAL_REMOTE_MODE) reports them too.
  // The exit list here is the restored reading; the caller swaps in the
  // printed one when EnumReading asks for it.
  set("LOCATE_MODE", &kLocateStatesList, &kLocateExitRestoredList);
  set("SPIRAL_REMOTE_MODE", &kLocateStatesList, &kLocateExitRestoredList);

  set("STORE_SAT_MODE", &kStoreStatesList, &kStoreExitList);
  // No track exit list is printed.
  set("TRACK_MODE", &kTrackStatesList, nullptr);
  set("STOW_MODE", &kStowStatesList, &kStowExitList);
  set("DEPLOY_MODE", &kDeployStatesList, &kDeployExitList);
  // "manual mode exit_status - use simple_exit_status"
  set("MANUAL_MODE", &kManualStatesList, &kSimpleExitList);
  // pos_confirm_states: "uses simple_exit_status"
  set("POS_CONFIRM_MODE", &kPosConfirmStatesList, &kSimpleExitList);
  // fairing_mode_states: "uses simple_exit"
  set("FAIRING_MODE", &kFairingStatesList, &kSimpleExitList);
  // truck_pos_mode_states: "uses simple exit"
  set("TRUCK_POS_MODE", &kTruckPosStatesList, &kSimpleExitList);
  set("INIT_MODE", &kInitStatesList, &kInitExitList);
  // setup_pack lists: shared by the two modes whose names they combine.
  set("SETUP_MODE", &kSetupPackStatesList, &kSetupPackExitList);
  set("PACK_MODE", &kSetupPackStatesList, &kSetupPackExitList);
  set("RECALL_MODE", &kRecallStatesList, &kRecallExitList);

  // No list: AUTO_MODE and DEPLOY_REQUEST_MODE (no list names them), the
  // maintenance/diagnostic modes DUMP_FLUXGATE_DATA_MODE .. GPSHDG_MODE
  // ("no maintenance modes are instrumented") and UNDEFINED_MODE.
  return a;
}

constexpr auto kAssignments = build_assignments();

const Assignment* assignment_for(std::uint8_t mode) {
  if (mode < kFirstValue) return nullptr;
  const std::size_t i = mode - kFirstValue;
  if (i >= kAssignments.size()) return nullptr;
  return &kAssignments[i];
}

const EnumList* apply_reading(const EnumList* list, const EnumReading& reading) {
  if (list == &kLocateExitRestoredList && !reading.restore_lost_locate_exit)
    return &kLocateExitPrintedList;
  if (list == &kTrackStatesList && reading.track_pol_states_as_manual_states) return &kTrackStatesManualOrderList;
  return list;
}

}  // namespace

std::optional<std::string_view> EnumList::name_of(std::uint8_t value) const {
  if (value < kFirstValue) return std::nullopt;
  const std::size_t i = value - kFirstValue;
  if (i >= names.size()) return std::nullopt;
  return names[i];
}

std::optional<std::uint8_t> EnumList::value_of(std::string_view n) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == n) return static_cast<std::uint8_t>(kFirstValue + i);
  return std::nullopt;
}

const EnumList& mode_names() { return kModeList; }

const EnumList* state_list_for_mode(std::uint8_t mode, const EnumReading& reading) {
  const Assignment* a = assignment_for(mode);
  return a ? apply_reading(a->states, reading) : nullptr;
}

const EnumList* exit_list_for_mode(std::uint8_t mode, const EnumReading& reading) {
  const Assignment* a = assignment_for(mode);
  return a ? apply_reading(a->exits, reading) : nullptr;
}

std::span<const EnumList* const> all_lists(const EnumReading& reading) {
  if (reading.track_pol_states_as_manual_states)
    return reading.restore_lost_locate_exit ? std::span<const EnumList* const>(kAllRestoredManualOrder)
                                            : std::span<const EnumList* const>(kAllPrintedManualOrder);
  return reading.restore_lost_locate_exit ? std::span<const EnumList* const>(kAllRestored)
                                          : std::span<const EnumList* const>(kAllPrinted);
}

}  // namespace sabus::enums
