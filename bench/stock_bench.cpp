// Cost of the stock model (issue 41 items 1 and 5): building a blisk-sized
// blank (r 130 mm, 50 mm high, a 30 mm bore) at 0.5 and 0.25 mm, and one
// move's update: a 1 mm feed of a D 10 bull-nose (r 1) slotting 5 mm deep
// with its axis along Z, the same tool tilted 20° and turning 0.5° per
// move (5-axis), and a 10 mm plunge with its retract; shank and holder
// checked against the stock unless the name says otherwise. Each move cuts
// fresh material: lines 12 mm apart across the blank, level after level.
// Memory: the stock's own bytes (rays and spans) as a counter.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "core/stock/stock.h"
#include "core/tools/tool.h"

namespace bliskrun {
namespace {

BlankProfile blisk_blank() { return BlankProfile({{30, 0}, {130, 0}, {130, 50}, {30, 50}}); }

Tool bull_nose() { return Tool::flat_end_mill({5, 1, 25, {10, 60}, {40, 40}}); }

Move feed_to(const Vec3& tip, const Vec3& axis) {
  Move m;
  m.kind = Move::Kind::Feed;
  m.pose = {tip, axis};
  return m;
}

// The k-th 1 mm move of the slotting path: lines along X at y 12 mm apart
// over the ring, 5 mm deeper for each pass over all lines.
struct SlotPath {
  int line = 0, level = 0;
  double x = -125;
  Vec3 tip() const { return {x, -110.0 + 12 * line, 50.0 - 5 * (level + 1)}; }
  void advance() {
    x += 1;
    if (x > 125) {
      x = -125;
      if (++line > 18) line = 0, ++level;
    }
  }
};

void counters(benchmark::State& state, const Stock& s) {
  state.counters["stock_MB"] = static_cast<double>(s.memory_bytes()) / (1 << 20);
  state.counters["spans"] = static_cast<double>(s.span_count());
}

void BM_StockBuild(benchmark::State& state) {
  const double h = state.range(0) / 100.0;
  std::unique_ptr<Stock> s;
  for (auto _ : state) s = std::make_unique<Stock>(blisk_blank(), StockOptions{h});
  counters(state, *s);
  state.counters["rays"] = static_cast<double>(s->ray_count());
}
BENCHMARK(BM_StockBuild)->Arg(50)->Arg(25)->Unit(benchmark::kMillisecond)->Iterations(2);

// One 1 mm slotting move per iteration; `tilt`: 20° and swinging.
void slot_moves(benchmark::State& state, bool tilt, bool body) {
  const double h = state.range(0) / 100.0;
  Stock s(blisk_blank(), {h});
  const Tool tool = bull_nose();
  CutOptions o;
  o.check_body = body;
  SlotPath path;
  long k = 0;
  const auto axis_at = [&](long i) {
    if (!tilt) return Vec3(Vec3::UnitZ());
    const double a = deg_to_rad(20), b = deg_to_rad(10 * std::sin(0.05 * static_cast<double>(i)));
    return Vec3(std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), std::cos(a));
  };
  ToolPose last{path.tip(), axis_at(0)};
  double removed = 0;
  long samples = 0;
  for (auto _ : state) {
    path.advance();
    ++k;
    const Move m = feed_to(path.tip(), axis_at(k));
    if (path.x == -125) {
      last = m.pose;  // a new line: start there
      continue;
    }
    const CutResult r = s.cut({m}, tool, o, &last);
    removed += r.removed_mm3;
    samples += r.samples;
    last = m.pose;
  }
  counters(state, s);
  state.counters["mm3_per_move"] = removed / static_cast<double>(state.iterations());
  state.counters["samples_per_move"] = static_cast<double>(samples) / static_cast<double>(state.iterations());
}

void BM_StockSlotMove(benchmark::State& state) { slot_moves(state, false, true); }
void BM_StockSlotMoveNoBodyCheck(benchmark::State& state) { slot_moves(state, false, false); }
void BM_StockFiveAxisMove(benchmark::State& state) { slot_moves(state, true, true); }
BENCHMARK(BM_StockSlotMove)->Arg(50)->Arg(25)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StockSlotMoveNoBodyCheck)->Arg(50)->Arg(25)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StockFiveAxisMove)->Arg(50)->Arg(25)->Unit(benchmark::kMicrosecond);

// A 10 mm plunge from 2 mm above the material and its retract, at fresh
// points 11 mm apart, level after level.
void BM_StockPlunge(benchmark::State& state) {
  const double h = state.range(0) / 100.0;
  Stock s(blisk_blank(), {h});
  const Tool tool = bull_nose();
  SlotPath path;
  double removed = 0;
  for (auto _ : state) {
    for (int i = 0; i < 11; ++i) path.advance();
    Vec3 bottom = path.tip();
    bottom.z() = 50.0 - 10 * (path.level + 1);
    const Vec3 top(bottom.x(), bottom.y(), bottom.z() + 12);
    const ToolPose from{top, Vec3::UnitZ()};
    const CutResult r = s.cut({feed_to(bottom, Vec3::UnitZ()), feed_to(top, Vec3::UnitZ())}, tool, {}, &from);
    removed += r.removed_mm3;
  }
  counters(state, s);
  state.counters["mm3_per_plunge"] = removed / static_cast<double>(state.iterations());
}
BENCHMARK(BM_StockPlunge)->Arg(50)->Arg(25)->Unit(benchmark::kMicrosecond);

// The stock after `slots` slots across it — a blisk's channels: a ray along
// X through the ring holds about one span per slot it crosses — and a 1 mm
// move per iteration along Y between two of them, 20 mm deep, axis along Z
// (the X grid's rays across the tool checked for material each placement).
// Whether a move's cost grows with the spans the rays hold (a job cuts every
// channel: does the 22nd cost more than the first?). Measured 2026-11-28:
// no (80-137 us CPU, falling as less material is left; a binary search for
// the spans in place of DexelRay's linear scans changed nothing measurable,
// and was not kept).
void BM_StockMoveAcrossSlots(benchmark::State& state) {
  const int slots = static_cast<int>(state.range(0));
  Stock s(blisk_blank(), {0.5});
  const Tool tool = bull_nose();
  Toolpath cuts;
  for (int k = 0; k < slots; ++k) {
    const double x = -120 + 240.0 * (k + 0.5) / slots;
    cuts.push_back(feed_to({x, -135, 30}, Vec3::UnitZ()));
    cuts.push_back(feed_to({x, 135, 30}, Vec3::UnitZ()));
    Move stop;
    stop.kind = Move::Kind::Stop;
    cuts.push_back(stop);
  }
  if (!cuts.empty()) s.cut(cuts, tool, {});
  const double x = slots > 1 ? -120 + 240.0 * 1.0 / slots : 60;  // between the first two slots
  double y = -125;
  ToolPose last{{x, y, 35}, Vec3::UnitZ()};
  for (auto _ : state) {
    y = y >= 125 ? -125 : y + 1;
    const Move m = feed_to({x, y, 35}, Vec3::UnitZ());
    if (y == -125) {
      last = m.pose;
      continue;
    }
    benchmark::DoNotOptimize(s.cut({m}, tool, {}, &last));
    last = m.pose;
  }
  counters(state, s);
}
BENCHMARK(BM_StockMoveAcrossSlots)->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace bliskrun
