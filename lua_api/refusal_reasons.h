#pragma once
// Why a plan refused what it refused, as its report gives it: one writer for
// the planners' wrappers (the drum, edge, hub and point-mill finishes, the
// repair paths), whose results name their refusals the same way (a `reason`
// on each refused contact, connection and lead).
#include <set>
#include <string>
#include <vector>

#include "lua_api/luax.h"

namespace bliskrun::lua_api {

// t.refusal_reasons = the distinct reasons (sorted), so a report says why,
// not only how many: the first 20 of the rows' refused contacts and of the
// refused links, then those of a refused lead-in and lead-out. For a
// finish result with rows[i].refusals, links and lead_in / lead_out (each
// `clear` or refused with a `reason`).
template <class FinishResult>
void set_refusal_reasons(lua_State* L, const FinishResult& r) {
  std::set<std::string> reasons;
  for (const auto& row : r.rows)
    for (const auto& refusal : row.refusals)
      if (reasons.size() < 20) reasons.insert(refusal.reason);
  for (const auto& link : r.links)
    if (!link.clear && reasons.size() < 20) reasons.insert(link.reason);
  for (const auto* end : {&r.lead_in, &r.lead_out})
    if (!end->clear && !end->reason.empty()) reasons.insert(end->reason);
  luax::set_strings(L, "refusal_reasons", reasons);
}

// t[key] = the reasons of the refused connections, in their order.
template <class Connections>
void set_refused_connections(lua_State* L, const char* key, const Connections& connections) {
  std::vector<std::string> reasons;
  for (const auto& c : connections)
    if (!c.clear) reasons.push_back(c.reason);
  luax::set_strings(L, key, reasons);
}

}  // namespace bliskrun::lua_api
