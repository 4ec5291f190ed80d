#pragma once
// Reading back the NC programs bliskrun writes, to prove them.
//
// The subset understood is what the posts in scripts/posts emit, in the four
// dialects (ISO/Fanuc, Siemens 840D, Heidenhain conversational, LinuxCNC):
//   - comments "( ... )" and "; ..." (the header's "VERDICT: ..." line is
//     one); "%" lines; block numbers "N10" or a leading Heidenhain block
//     number; program numbers "O1000"; "BEGIN PGM ... / END PGM ..." lines;
//     a line ending in "~" (after its comment) continues the block on the
//     next line, as the TNC writes cycle parameters;
//   - G0 G1 (modal), G90 (G91 is refused), G93 G94 (feed mode), G17, G21/G71
//     (mm; inch is refused), G40 G43 G61 G64 G80, G43.4 / G43.5 (TCP on),
//     G49 (TCP off);
//   - work offsets: G54-G59 (offsets 1-6), G59.1-G59.3 (LinuxCNC, 7-9),
//     G505-G599 (Siemens, 5-99; its G58/G59 are axial programmable offsets
//     there, which no post writes: read as ISO's 5 and 6); Heidenhain "CYCL
//     DEF 247 DATUM SETTING" with its one parameter "Q339=+n" (preset table
//     row n), no other cycle;
//   - TRAORI / TRAFOOF (Siemens), M128 / M129 and FUNCTION TCPM / FUNCTION
//     RESET TCPM (Heidenhain) switch TCP control on / off; FUNCTION TCPM's
//     PATHCTRL VECTOR makes the tool axis follow the great circle
//     (ProgramMove::vector), PATHCTRL AXIS (the default) the rotary axes;
//   - Heidenhain "M94 C" (or "M94" for both rotaries): the display of the
//     rotary axis is reduced to [0, 360) deg without motion;
//   - Heidenhain "L" blocks with FMAX (rapid) or F (feed) and R0;
//     "TOOL CALL n Z Ssss";
//   - words X Y Z and the machine's two rotary axes (A/B/C, degrees), F, S,
//     T, D, H, M (M128/M129 as above, every other M passes: spindle,
//     coolant, tool change, end).
// Anything else is an error "<file>:<line>: column <c>: ..." so a program we
// cannot prove is never reported as proven.
#include <array>
#include <string>
#include <vector>

#include "core/machine/kinematics.h"
#include "core/machine/motion.h"

namespace bliskrun {

struct ProgramMove {
  int line = 0;  // 1-based line of the block in the program
  MoveKind kind = MoveKind::Feed;
  // Machine axis words in effect after the block (rotaries in radians). With
  // TCP control on, linear_mm is the programmed tool tip in the part frame.
  MachineAxes axes;
  bool tcp = false;
  bool vector = false;  // TCP with the axis on the great circle (PATHCTRL VECTOR)
  // Turns (360 deg) taken off each rotary axis' display before this block
  // (M94), so the block starts from the reduced value.
  std::array<int, 2> rotary_reset{0, 0};
  FeedMode feed_mode = FeedMode::PerMinute;
  double feed = 0;  // F in effect (mm/min or 1/min)
  int tool = 0;
  // The work offset the program selected before this block: n of G54+n-1
  // (G505 = 5 ...), of G59.n (6+n), or the TNC's preset n; 0: none selected.
  int work_offset = 0;
};

struct ProgramReadOptions {
  std::string file_name = "program";  // used in error messages
  // TCP control on from the first block (LinuxCNC with trt kinematics has no
  // switch: its XYZ are always the tip in the part frame).
  bool tcp = false;
  MachineAxes start;  // axis values before the first block
};

// Parses `text` into the moves it commands, in order. Throws DataError at the
// first block it cannot read, naming line and column.
std::vector<ProgramMove> read_program(const std::string& text, const MachineDefinition& machine,
                                      const ProgramReadOptions& options);

}  // namespace bliskrun
