// `silt check`: the compiled model in words and numbers, module by module.
#include <sstream>

#include "silt/module.hpp"

namespace silt {

std::string step_text(const Model& m) {
  if (!m.dt_text.empty()) return m.dt_text;
  std::ostringstream o;
  o.precision(5);
  o << "adaptive time step: the first " << m.dt << m.unit("s");
  return o.str();
}

std::string describe(const Model& m) {
  std::ostringstream o;
  o.precision(5);
  for (const Module& mod : modules())
    if (mod.spec->describe && m.module_on(mod.spec->name)) o << mod.spec->describe(m);
  if (!m.gives_run_length())
    o << "run          no run length ([run] steps or time): silt run needs --steps or --time (the shell: run N, "
         "run Ts)";
  else if (m.adaptive_dt && m.run_time >= 0)
    o << "run          until t = " << m.run_time << m.unit("s") << " (" << step_text(m) << ")";
  else if (m.adaptive_dt) o << "run          " << m.run_steps << " steps (" << step_text(m) << ")";
  else o << "run          " << m.run_steps << " steps = " << m.run_steps * m.dt << m.unit("s");
  o << (m.until_static.on ? ", or until static" : "") << (m.stop_when_steady ? ", or until steady" : "") << "\n";
  o << "observe      ";
  for (size_t k = 0; k < m.observe.size(); ++k) o << m.observe[k] << (k + 1 < m.observe.size() ? ", " : "");
  o << " every " << m.sample_every << " steps\n";
  return o.str();
}

}  // namespace silt
