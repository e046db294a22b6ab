#include "preadaptive_mrac/jsbsim/jsbsim_overlay.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "preadaptive_mrac/jsbsim/jsbsim_paths.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_process.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_xml.hpp"

namespace preadaptive_mrac {

namespace fs = std::filesystem;

namespace {

constexpr char kInterfaceProperty[] = "fcs/pmrac-elevator-cmd-rad";
constexpr char kCommand[] = "fcs/elevator-cmd-norm";
constexpr char kPosition[] = "fcs/elevator-pos-rad";
// Where the surface drive moves the aircraft's own (trimmed) elevator deflection.
constexpr char kAircraftPosition[] = "pmrac/aircraft/elevator-pos-rad";
constexpr char kGeneratedIc[] = "pmrac_operating_point";
constexpr int kMaxDepth = 40;

std::string readText(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

std::optional<double> number(const std::string& text) {
  const std::string t = trimmed(text);
  if (t.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size()) return std::nullopt;
  return v;
}

std::optional<double> childNumber(const XmlElement& e, const char* name) {
  const XmlElement* c = e.child(name);
  return c ? number(c->text) : std::nullopt;
}

/// JSBSim's own property of a component named `name` (FGPropertyManager::mkPropertyName):
/// lower case, spaces as '-', under fcs/ unless the name has a '/'.
std::string componentProperty(const std::string& name) {
  std::string n = trimmed(name);
  for (char& c : n) {
    if (std::isspace(static_cast<unsigned char>(c)))
      c = '-';
    else
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return n.find('/') == std::string::npos ? "fcs/" + n : n;
}

std::string fmt(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

/// One parsed file of the aircraft: the aircraft file itself or a system file it names.
struct Doc {
  fs::path path;  ///< where it was read
  std::string text;
  std::unique_ptr<XmlElement> root;
  TextEdits edits;
};

struct Component {
  const XmlElement* e = nullptr;
  const XmlElement* section = nullptr;  ///< the <flight_control>, <system> or <autopilot>
  Doc* doc = nullptr;
  std::vector<const XmlElement*> inputs;  ///< the <input> elements
};

/// An <input>'s property and whether it is negated (written '-property'; the text is trimmed).
std::pair<std::string, bool> inputRef(const XmlElement& in) {
  const bool negated = !in.text.empty() && in.text[0] == '-';
  return {trimmed(negated ? in.text.substr(1) : in.text), negated};
}

std::string describe(const Component& c) {
  return "<" + c.e->name + "> '" + c.e->attribute("name") + "'";
}

/// The aircraft's FCS: every component of every channel, indexed by the properties it writes.
class Fcs {
 public:
  Fcs(const fs::path& root, const std::string& aircraft) : root_(root), aircraft_(aircraft) {
    const fs::path file = root / "aircraft" / aircraft / (aircraft + ".xml");
    docs_.push_back(load(file, "plant.jsbsim.aircraft"));
    const XmlElement& top = *docs_[0]->root;
    for (const char* kind : {"system", "autopilot", "flight_control"})
      for (const XmlElement* s : top.childrenNamed(kind)) addSection(*s, docs_[0].get());
  }

  Doc& aircraftDoc() { return *docs_[0]; }
  std::vector<std::unique_ptr<Doc>>& docs() { return docs_; }

  /// Every component, in the order JSBSim's files list them.
  const std::vector<Component>& components() const { return all_; }

  const Component* writer(const std::string& property) const {
    const auto it = writers_.find(property);
    return it == writers_.end() ? nullptr : &it->second;
  }

  /// The gain from fcs/elevator-cmd-norm to `property` through the chain of components;
  /// `path` gets the components from the surface back to the command. Empty when the chain
  /// does not reach the command or passes a component whose gain is not a number (`blocked`).
  std::optional<double> gainFrom(const std::string& property, int depth,
                                 std::vector<const Component*>* path, std::string* blocked) const {
    if (property == kCommand) return 1.0;
    const Component* c = writer(property);
    if (c == nullptr || depth > kMaxDepth) return std::nullopt;
    for (const XmlElement* in : c->inputs) {
      const auto [in_property, negated] = inputRef(*in);
      std::vector<const Component*> sub;
      const std::optional<double> g = gainFrom(in_property, depth + 1, &sub, blocked);
      if (!g) continue;
      const std::optional<double> own = localGain(*c);
      if (!own) {
        if (blocked->empty()) *blocked = describe(*c);
        return std::nullopt;
      }
      path->push_back(c);
      path->insert(path->end(), sub.begin(), sub.end());
      return (negated ? -1.0 : 1.0) * *own * *g;
    }
    return std::nullopt;
  }

  /// A component's gain from input to output near zero, when it is a number.
  static std::optional<double> localGain(const Component& c) {
    const XmlElement& e = *c.e;
    const std::string& t = e.name;
    if (t == "summer" || t == "actuator" || t == "lag_filter" || t == "sensor" || t == "deadband")
      return 1.0;
    if (t == "pure_gain") return childNumber(e, "gain");
    if (t == "aerosurface_scale") {
      const std::optional<double> gain = e.child("gain") ? childNumber(e, "gain") : 1.0;
      const XmlElement* dom = e.child("domain");
      const XmlElement* rng = e.child("range");
      if (!gain || rng == nullptr) return std::nullopt;
      const auto dmin = dom ? childNumber(*dom, "min") : -1.0;
      const auto dmax = dom ? childNumber(*dom, "max") : 1.0;
      const auto rmin = childNumber(*rng, "min");
      const auto rmax = childNumber(*rng, "max");
      if (!dmin || !dmax || !rmin || !rmax || *dmax == *dmin) return std::nullopt;
      const XmlElement* zc = e.child("zero_centered");
      const bool zero_centered = zc == nullptr || !(zc->text == "0" || zc->text == "false");
      // Zero centred: the two halves scale separately; the mean of their slopes (exact for a
      // symmetric travel).
      if (zero_centered && *dmin < 0.0 && *dmax > 0.0)
        return *gain * 0.5 * (*rmax / *dmax + *rmin / *dmin);
      return *gain * (*rmax - *rmin) / (*dmax - *dmin);
    }
    return std::nullopt;
  }

 private:
  std::unique_ptr<Doc> load(const fs::path& file, const char* key) {
    auto d = std::make_unique<Doc>();
    d->path = file;
    d->text = readText(file);
    try {
      d->root = parseXml(d->text);
    } catch (const XmlError& e) {
      throw JsbsimError(std::string(key) + ": " + file.string() + " is " + e.what());
    }
    return d;
  }

  /// A system file as JSBSim looks for it: the aircraft's folder, its Systems/, root/systems.
  fs::path findSystemFile(const std::string& name) const {
    const fs::path dir = root_ / "aircraft" / aircraft_;
    for (const fs::path& base : {dir, dir / "Systems", root_ / "systems"}) {
      for (const std::string& n : {name, name + ".xml"}) {
        if (fs::is_regular_file(base / n)) return base / n;
      }
    }
    throw JsbsimError("plant.jsbsim.aircraft, plant.jsbsim.root: the aircraft '" + aircraft_ +
                      "' names the system file '" + name + "', which is in none of " +
                      dir.string() + ", " + (dir / "Systems").string() + ", " +
                      (root_ / "systems").string());
  }

  void addSection(const XmlElement& s, Doc* doc) {
    const std::string file = s.attribute("file");
    if (!file.empty()) {
      docs_.push_back(load(findSystemFile(file), "plant.jsbsim.aircraft"));
      Doc* d = docs_.back().get();
      addSection(*d->root, d);
      return;
    }
    for (const XmlElement* ch : s.childrenNamed("channel")) {
      for (const auto& e : ch->children) {
        if (e->name == "description" || e->children.empty()) continue;
        Component c;
        c.e = e.get();
        c.section = &s;
        c.doc = doc;
        c.inputs = e->childrenNamed("input");
        writers_[componentProperty(e->attribute("name"))] = c;
        all_.push_back(c);
        for (const XmlElement* out : e->childrenNamed("output")) writers_[trimmed(out->text)] = c;
      }
    }
  }

  fs::path root_;
  std::string aircraft_;
  std::vector<std::unique_ptr<Doc>> docs_;
  std::map<std::string, Component> writers_;
  std::vector<Component> all_;
};

/// The limits of the chain `path` (surface first): the travel of the component nearest the
/// surface that clips or scales, the rate of the actuator nearest it.
void takeLimits(const std::vector<const Component*>& path, JsbsimElevator* el) {
  double downstream = 1.0;  // the gain from a component's output to the surface
  bool travel = false, rate = false;
  for (const Component* c : path) {
    const XmlElement& e = *c->e;
    if (!travel) {
      const XmlElement* clip = e.child("clipto");
      const XmlElement* rng = e.name == "aerosurface_scale" ? e.child("range") : nullptr;
      const XmlElement* lim = clip ? clip : rng;
      if (lim) {
        const auto lo = childNumber(*lim, "min");
        const auto hi = childNumber(*lim, "max");
        double g = downstream;
        if (lim == rng && e.child("gain")) g *= childNumber(e, "gain").value_or(1.0);
        if (lo && hi) {
          el->min_rad = std::min(*lo * g, *hi * g);
          el->max_rad = std::max(*lo * g, *hi * g);
          travel = true;
        }
      }
    }
    if (!rate && e.name == "actuator") {
      double r = 0.0;
      for (const XmlElement* rl : e.childrenNamed("rate_limit")) {
        const auto v = number(rl->text);
        if (v && *v > 0.0) r = r > 0.0 ? std::min(r, *v) : *v;
      }
      if (r > 0.0) {
        el->max_rate = r * std::abs(downstream);
        rate = true;
      }
    }
    const auto g = Fcs::localGain(*c);
    if (!g) break;
    downstream *= *g;
  }
}

std::string noElevator(const std::string& aircraft, const std::string& cause) {
  return "plant.jsbsim.aircraft: the aircraft '" + aircraft +
         "' has no elevator the package can find: " + cause +
         " (the package drives the pitch axis through fcs/elevator-cmd-norm and "
         "fcs/elevator-pos-rad, JSBSim's standard names)";
}

/// The pmrac-interface system: the package's inputs and, for the command drive, the elevator
/// command in the aircraft's units.
std::string interfaceSystem(JsbsimElevatorDrive drive, double rad_per_command) {
  std::string s =
      "\n  <!-- Added by preadaptive_mrac (an overlay: the aircraft's own file is unchanged). -->\n"
      "  <system name=\"pmrac-interface\">\n"
      "    <property value=\"0.0\"> fcs/pmrac-elevator-cmd-rad </property>\n"
      "    <property value=\"1.0\"> pmrac/fault/elevator-effectiveness </property>\n"
      "    <property value=\"1.0\"> pmrac/fault/pitch-damping </property>\n"
      "    <property value=\"0.0\"> pmrac/fault/cg-shift-mac </property>\n";
  for (const char* r : {"alpha-rad", "q-rad_sec", "theta-rad", "gamma-rad", "vt-fps", "h-sl-ft"})
    s += std::string("    <property value=\"0.0\"> pmrac/ref/") + r + " </property>\n";
  if (drive == JsbsimElevatorDrive::kCommand) {
    s += "    <channel name=\"pmrac-elevator\">\n"
         "      <fcs_function name=\"pmrac/elevator-command\">\n"
         "        <function> <product> <property>fcs/pmrac-elevator-cmd-rad</property> <value>" +
         fmt(1.0 / rad_per_command) +
         "</value> </product> </function>\n"
         "        <output>fcs/elevator-cmd-norm</output>\n"
         "      </fcs_function>\n"
         "    </channel>\n";
  }
  s += "  </system>\n";
  return s;
}

/// The outputs, computed by the aerodynamics (after the integrator and the auxiliary model of
/// the same pass) as in b747_pmrac.
std::string interfaceOutputs() {
  std::string s = "\n    <!-- Added by preadaptive_mrac: the package's outputs. -->\n";
  const char* const pairs[][2] = {
      {"alpha-rad", "aero/alpha-rad"},     {"q-rad_sec", "velocities/q-rad_sec"},
      {"theta-rad", "attitude/theta-rad"}, {"gamma-rad", "flight-path/gamma-rad"},
      {"vt-fps", "velocities/vt-fps"},     {"h-sl-ft", "position/h-sl-ft"}};
  for (const auto& p : pairs)
    s += std::string("    <function name=\"pmrac/dev/") + p[0] + "\"> <difference> <property>" +
         p[1] + "</property> <property>pmrac/ref/" + p[0] +
         "</property> </difference> </function>\n";
  s += "    <function name=\"pmrac/sync/frame\"> <property>simulation/frame</property> "
       "</function>\n";
  return s;
}

std::string surfaceChannel() {
  return std::string(
             "\n    <!-- Added by preadaptive_mrac: the surface is the aircraft's own deflection "
             "plus the package's. -->\n"
             "    <channel name=\"pmrac-surface\">\n"
             "      <fcs_function name=\"pmrac/elevator-surface\">\n"
             "        <function> <sum> <property>") +
         kAircraftPosition +
         "</property> <property>fcs/pmrac-elevator-cmd-rad</property> </sum> </function>\n"
         "        <output>fcs/elevator-pos-rad</output>\n"
         "      </fcs_function>\n"
         "    </channel>\n  ";
}

/// A level start at the operating point, clear of the ground (the terrain 5000 ft below), the
/// engines running; latitude 0 heading north keeps the Earth's rotation out of the lateral axes.
std::string operatingPointIc(const JsbsimParams& p) {
  return "<?xml version=\"1.0\"?>\n<!-- Generated by preadaptive_mrac: a level start at the "
         "operating point (plant.jsbsim.mach, plant.jsbsim.altitude_ft). -->\n"
         "<initialize name=\"" +
         std::string(kGeneratedIc) +
         "\">\n"
         "  <latitude unit=\"DEG\"> 0.0 </latitude>\n"
         "  <longitude unit=\"DEG\"> 0.0 </longitude>\n"
         "  <elevation unit=\"FT\"> " +
         fmt(p.altitude_ft - 5000.0) +
         " </elevation>\n"
         "  <altitude unit=\"FT\"> 5000.0 </altitude>\n"
         "  <psi unit=\"DEG\"> 0.0 </psi>\n"
         "  <phi unit=\"DEG\"> 0.0 </phi>\n"
         "  <mach> " +
         fmt(p.mach) +
         " </mach>\n"
         "  <alpha unit=\"DEG\"> 0.0 </alpha>\n"
         "  <beta unit=\"DEG\"> 0.0 </beta>\n"
         "  <gamma unit=\"DEG\"> 0.0 </gamma>\n"
         "  <running> -1 </running>\n"
         "</initialize>\n";
}

/// `from`'s tree mirrored under `to`: folders made, files linked.
void mirror(const fs::path& from, const fs::path& to) {
  fs::create_directories(to);
  for (const auto& entry : fs::directory_iterator(from)) {
    const fs::path target = to / entry.path().filename();
    if (entry.is_directory())
      mirror(entry.path(), target);
    else
      fs::create_symlink(fs::absolute(entry.path()), target);
  }
}

/// What the overlay changes: the aircraft's elevator found and every edit queued.
JsbsimElevator planOverlay(Fcs* fcs, const std::string& aircraft, JsbsimElevatorDrive drive) {
  const Component* w = fcs->writer(kPosition);
  if (w == nullptr)
    throw JsbsimError(noElevator(
        aircraft,
        "no component of its flight control system (<flight_control>, <autopilot>, <system>) "
        "writes fcs/elevator-pos-rad"));
  JsbsimElevator el;
  el.writer = describe(*w);
  std::vector<const Component*> path;
  std::string blocked;
  const std::optional<double> g = fcs->gainFrom(kPosition, 0, &path, &blocked);
  if (drive == JsbsimElevatorDrive::kCommand) {
    if (!g || !(std::abs(*g) > 0.0))
      throw JsbsimError("plant.jsbsim.elevator: the aircraft '" + aircraft +
                        "' has its elevator (" + el.writer +
                        " writes fcs/elevator-pos-rad) but the package cannot follow it back to "
                        "fcs/elevator-cmd-norm through summers, gains, scales and actuators" +
                        (blocked.empty() ? std::string() : " (it passes " + blocked + ")") +
                        ": set plant.jsbsim.elevator to surface to drive the surface directly");
    el.rad_per_command = *g;
  }
  if (path.empty()) path.push_back(w);
  takeLimits(path, &el);

  Doc& ac = fcs->aircraftDoc();
  const XmlElement& top = *ac.root;
  const XmlElement* aero = top.child("aerodynamics");
  if (aero == nullptr || !aero->attribute("file").empty() || aero->open_end == aero->close_end)
    throw JsbsimError("plant.jsbsim.aircraft: the aircraft '" + aircraft +
                      "' has no inline <aerodynamics> element, where the package adds its "
                      "outputs (an <aerodynamics file=...> is not supported)");
  // The interface system loads first (JSBSim loads every <system> before the autopilot and
  // the flight control, in file order), so its command reaches the FCS in the same pass.
  size_t at = top.close_begin;
  for (const auto& c : top.children)
    if (c->name == "system" || c->name == "autopilot" || c->name == "flight_control") {
      at = c->open_begin;
      break;
    }
  ac.edits.insert(at, interfaceSystem(drive, el.rad_per_command) + "\n  ");
  ac.edits.insert(aero->open_end, interfaceOutputs());
  if (drive == JsbsimElevatorDrive::kSurface) {
    const XmlElement* out = nullptr;
    for (const XmlElement* o : w->e->childrenNamed("output"))
      if (trimmed(o->text) == kPosition) out = o;
    if (out == nullptr)
      throw JsbsimError(noElevator(aircraft, el.writer + " writes fcs/elevator-pos-rad without "
                                                         "an <output>, which the package moves"));
    w->doc->edits.replace(out->open_end, out->close_begin - out->open_end, kAircraftPosition);
    w->doc->edits.insert(w->section->close_begin, surfaceChannel());
  }
  return el;
}

/// The speed hold's throttle correction: a thrust change of -2 W/V0 per ft/s of airspeed above
/// the trim's (V0 = ic/vt-fps, the speed the trim holds), in throttle through the aircraft's
/// thrust per unit throttle, taken as its propulsive force over its throttle command (exact for
/// a thrust proportional to the throttle). Stateless: JSBSim runs its models twice a step in the
/// lockstep, so an integrator there would not integrate over time.
std::string speedHoldCorrection() {
  return "      <fcs_function name=\"pmrac/speed-hold/throttle-correction\">\n"
         "        <function> <product> <value>-2.0</value> "
         "<property>inertia/weight-lbs</property>\n"
         "          <difference> <property>velocities/vt-fps</property> "
         "<property>ic/vt-fps</property> </difference>\n"
         "          <quotient> <property>fcs/throttle-cmd-norm[0]</property>\n"
         "            <product> <property>ic/vt-fps</property> <max> "
         "<property>forces/fbx-prop-lbs</property> <value>1.0</value> </max> </product>\n"
         "          </quotient> </product> </function>\n"
         "      </fcs_function>\n";
}

/// Engine i's throttle: the trim's command plus the correction, within 0..1; written to
/// fcs/throttle-pos-norm[i] when `to_position` (no component of the aircraft reads the command).
std::string speedHoldThrottle(size_t i, bool to_position) {
  const std::string n = std::to_string(i);
  return "      <fcs_function name=\"pmrac/speed-hold/throttle-" + n +
         "\">\n"
         "        <function> <max> <value>0.0</value> <min> <value>1.0</value> <sum> "
         "<property>fcs/throttle-cmd-norm[" +
         n +
         "]</property> <property>pmrac/speed-hold/throttle-correction</property> </sum> </min> "
         "</max> </function>\n" +
         (to_position ? "        <output>fcs/throttle-pos-norm[" + n + "]</output>\n" : "") +
         "      </fcs_function>\n";
}

/// The speed hold added to the overlay: every component that reads an engine's
/// fcs/throttle-cmd-norm reads the held throttle instead; an engine whose command no component
/// reads (JSBSim then copies it to the position) gets the held throttle at its position.
void planSpeedHold(Fcs* fcs, const std::string& aircraft) {
  const XmlElement& top = *fcs->aircraftDoc().root;
  const XmlElement* propulsion = top.child("propulsion");
  const size_t engines = propulsion ? propulsion->childrenNamed("engine").size() : 0;
  if (engines == 0)
    throw JsbsimError(
        "plant.jsbsim.speed_hold: the aircraft '" + aircraft +
        "' has no <engine> in its <propulsion>: set plant.jsbsim.speed_hold to false");
  std::string channel = speedHoldCorrection();
  const fs::path folder = fcs->aircraftDoc().path.parent_path();
  for (size_t i = 0; i < engines; ++i) {
    const std::string cmd = "fcs/throttle-cmd-norm[" + std::to_string(i) + "]";
    bool read = false;
    for (const Component& c : fcs->components()) {
      for (const XmlElement* in : c.inputs) {
        const auto [name, negated] = inputRef(*in);
        if (name != cmd && !(i == 0 && name == "fcs/throttle-cmd-norm")) continue;
        const fs::path rel = fs::relative(c.doc->path, folder);
        if (rel.empty() || rel.native().rfind("..", 0) == 0)
          throw JsbsimError("plant.jsbsim.speed_hold: the aircraft '" + aircraft +
                            "' reads its throttle command in " + c.doc->path.string() +
                            ", outside its folder, which the overlay does not rewrite: set "
                            "plant.jsbsim.speed_hold to false");
        c.doc->edits.replace(
            in->open_end, in->close_begin - in->open_end,
            std::string(negated ? "-" : "") + "pmrac/speed-hold/throttle-" + std::to_string(i));
        read = true;
      }
    }
    const std::string pos = "fcs/throttle-pos-norm[" + std::to_string(i) + "]";
    const Component* w = fcs->writer(pos);
    if (w == nullptr && i == 0) w = fcs->writer("fcs/throttle-pos-norm");
    if (!read && w != nullptr)
      throw JsbsimError("plant.jsbsim.speed_hold: the aircraft '" + aircraft + "' writes " + pos +
                        " in " + describe(*w) + ", which does not read " + cmd +
                        " as an <input>: set plant.jsbsim.speed_hold to false");
    channel += speedHoldThrottle(i, !read);
  }
  size_t at = top.close_begin;
  for (const auto& c : top.children)
    if (c->name == "system" || c->name == "autopilot" || c->name == "flight_control") {
      at = c->open_begin;
      break;
    }
  fcs->aircraftDoc().edits.insert(
      at,
      "<!-- Added by preadaptive_mrac: the speed hold (plant.jsbsim.speed_hold). -->\n"
      "  <system name=\"pmrac-speed-hold\">\n    <channel name=\"pmrac-speed-hold\">\n" +
          channel + "    </channel>\n  </system>\n\n  ");
}

}  // namespace

double JsbsimElevator::symmetricTravel() const {
  return travelKnown() ? std::min(std::abs(min_rad), std::abs(max_rad)) : 0.0;
}

bool jsbsimHasInterface(const std::string& aircraft_xml) {
  return aircraft_xml.find(kInterfaceProperty) != std::string::npos;
}

JsbsimElevator findJsbsimElevator(const std::string& root, const std::string& aircraft,
                                  JsbsimElevatorDrive drive) {
  Fcs fcs(root, aircraft);
  return planOverlay(&fcs, aircraft, drive);
}

std::optional<JsbsimElevator> jsbsimOrdinaryElevator(const JsbsimParams& params) {
  findJsbsimExecutable(params.executable);  // a missing JSBSim is said first, as by the plant
  const std::string root = findJsbsimRoot(params.root, params.aircraft);
  const fs::path file = fs::path(root) / "aircraft" / params.aircraft / (params.aircraft + ".xml");
  if (jsbsimHasInterface(readText(file))) return std::nullopt;
  return findJsbsimElevator(root, params.aircraft, params.elevator);
}

JsbsimOverlay::JsbsimOverlay(const std::string& root, const JsbsimParams& params)
    : root_(root), initialize_(params.initialize) {
  const fs::path src = fs::path(root) / "aircraft" / params.aircraft;
  if (jsbsimHasInterface(readText(src / (params.aircraft + ".xml")))) return;
  Fcs fcs(root, params.aircraft);
  elevator_ = planOverlay(&fcs, params.aircraft, params.elevator);
  if (params.speed_hold) planSpeedHold(&fcs, params.aircraft);
  dir_ = makeJsbsimTempDir("pmrac_overlay_");
  try {
    // The root's other folders (engine/, systems/, ...) linked; the aircraft's folder mirrored
    // file by file, so a rewritten file can take its place.
    for (const auto& entry : fs::directory_iterator(root))
      if (entry.path().filename() != "aircraft")
        fs::create_symlink(fs::absolute(entry.path()), fs::path(dir_) / entry.path().filename());
    const fs::path dst = fs::path(dir_) / "aircraft" / params.aircraft;
    mirror(src, dst);
    for (auto& d : fcs.docs()) {
      if (d->edits.empty()) continue;
      const fs::path rel = fs::relative(d->path, src);
      if (rel.empty() || rel.native().rfind("..", 0) == 0)
        throw JsbsimError("plant.jsbsim.elevator: the aircraft '" + params.aircraft +
                          "' has its elevator in " + d->path.string() +
                          ", outside its folder; the surface drive rewrites only files in it: "
                          "set plant.jsbsim.elevator to command");
      fs::remove(dst / rel);
      std::ofstream(dst / rel) << d->edits.apply(d->text);
    }
    root_ = dir_;
    if (params.initialize == JsbsimParams{}.initialize &&
        !fs::exists(src / (params.initialize + ".xml"))) {
      initialize_ = kGeneratedIc;
      std::ofstream(dst / (initialize_ + ".xml")) << operatingPointIc(params);
    }
  } catch (const fs::filesystem_error& e) {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    throw JsbsimError(std::string("JSBSim: cannot build the aircraft overlay: ") + e.what());
  } catch (...) {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    throw;
  }
}

JsbsimOverlay::~JsbsimOverlay() {
  if (dir_.empty()) return;
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

}  // namespace preadaptive_mrac
