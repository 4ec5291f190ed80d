#include "core/toolpath/apt.h"

#include <cstdio>

namespace bliskrun {

namespace {
void put_goto(std::ostream& os, const ToolPose& p) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "GOTO/%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", p.tip.x(), p.tip.y(), p.tip.z(),
                p.axis.x(), p.axis.y(), p.axis.z());
  os << buf;
}
}  // namespace

void write_apt_moves(std::ostream& os, const Toolpath& moves,
                     const std::function<std::string(int row)>& row_header, const char* stop_label) {
  int row = -1;
  for (const Move& m : moves) {
    switch (m.kind) {
      case Move::Kind::Stop:
        os << "$$ " << stop_label << ": " << m.reason << "\nSTOP\n";
        break;
      case Move::Kind::Rapid:
        os << "RAPID\n";
        put_goto(os, m.pose);
        break;
      case Move::Kind::Feed:
        if (m.row != row) {
          row = m.row;
          os << row_header(row);
        }
        put_goto(os, m.pose);
        break;
    }
  }
}

}  // namespace bliskrun
