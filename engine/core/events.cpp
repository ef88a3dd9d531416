// Names of the numerical events, and the events modules register.
#include <stdexcept>
#include <vector>

#include "silt/events.hpp"

namespace silt {
namespace {

std::vector<std::string>& names() {
  static std::vector<std::string> n = {"non_finite_late", "non_finite", "overlap",
                                       "box_collapse",    "runaway",    "clock_stalled"};
  return n;
}

}  // namespace

EventId register_module_event(const std::string& name) {
  auto& n = names();
  for (size_t k = 0; k < n.size(); ++k)
    if (n[k] == name) return static_cast<EventId>(k);
  if (n.size() >= static_cast<size_t>(kMaxEvents)) throw std::logic_error("too many event kinds (kMaxEvents)");
  n.push_back(name);
  return static_cast<EventId>(n.size() - 1);
}

const std::string& event_name(EventId e) { return names().at(e); }

}  // namespace silt
