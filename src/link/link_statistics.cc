#include "src/link/link_statistics.h"

#include <nlohmann/json.hpp>

namespace robossis::link {

nlohmann::ordered_json ToJson(const FollowerLinkStatistics& s) {
  return {{"setpoints_received", s.setpoints_received}, {"setpoints_accepted", s.setpoints_accepted},
          {"dropped_stale", s.dropped_stale},           {"dropped_replayed", s.dropped_replayed},
          {"dropped_session", s.dropped_session},       {"rejected_invalid", s.rejected_invalid},
          {"commands_received", s.commands_received},   {"commands_dropped", s.commands_dropped},
          {"commands_replayed", s.commands_replayed},   {"commands_stale", s.commands_stale},
          {"status_published", s.status_published},     {"deadline_missed", s.deadline_missed},
          {"leaders_alive", s.leaders_alive},           {"estops_received", s.estops_received}};
}

nlohmann::ordered_json ToJson(const LeaderLinkStatistics& s) {
  return {{"setpoints_sent", s.setpoints_sent},   {"commands_sent", s.commands_sent},
          {"commands_refused", s.commands_refused}, {"status_received", s.status_received},
          {"state_received", s.state_received},   {"followers_matched", s.followers_matched},
          {"estops_sent", s.estops_sent}};
}

}  // namespace robossis::link
