#pragma once
// The APT/CL body of any toolpath (core/toolpath/move.h): each planner's
// *_apt writes its own header ($$ lines naming the operation, tool and
// tolerances, MULTAX) and FINI around it.
#include <functional>
#include <ostream>
#include <string>

#include "core/toolpath/move.h"

namespace bliskrun {

// RAPID before each rapid, GOTO/x,y,z,i,j,k (tip and axis, 6 decimals) for
// each Feed and Rapid, and "$$ <stop_label>: reason" then STOP for a Stop;
// `row_header(row)` is written before the first feed of each row.
void write_apt_moves(std::ostream& os, const Toolpath& moves,
                     const std::function<std::string(int row)>& row_header, const char* stop_label = "REFUSED");

}  // namespace bliskrun
