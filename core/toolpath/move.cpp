#include "core/toolpath/move.h"

#include <utility>

namespace bliskrun {

const char* to_string(Move::Kind kind) {
  switch (kind) {
    case Move::Kind::Feed: return "feed";
    case Move::Kind::Rapid: return "rapid";
    case Move::Kind::Stop: return "stop";
  }
  return "?";
}

ToolpathPasses toolpath_passes(const Toolpath& moves) {
  ToolpathPasses out;
  std::vector<ToolPose> pass;
  auto close = [&] {
    if (!pass.empty()) out.passes.push_back(std::move(pass));
    pass.clear();
  };
  for (size_t i = 0; i < moves.size(); ++i) {
    if (moves[i].kind == Move::Kind::Stop) {
      close();
      continue;
    }
    if (pass.empty()) out.first_move.push_back(static_cast<long>(i));
    pass.push_back(moves[i].pose);
  }
  close();
  return out;
}

}  // namespace bliskrun
