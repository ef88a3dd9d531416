#include "silt/contacts.hpp"

namespace silt {

std::vector<Contact> touching_contacts(const State& s) {
  std::vector<Contact> out;
  for_each_contact(s, [&](const Contact& c) { out.push_back(c); });
  return out;
}

}  // namespace silt
