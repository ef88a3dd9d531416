// Bad scenes are refused with file:line:col and a useful message.
#include <doctest/doctest.h>

#include "silt/scene.hpp"
#include "silt/text.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

const char* kGood = R"([scene]
dimension = 3
[domain]
lo = [0, 0, 0]
hi = [10, 10, 10]
[contact]
model = "hooke"
k_n = 1e5
[[grains]]
count = 10
radius = 0.5
[run]
dt = 1e-4
)";

std::string with(const std::string& from, const std::string& to) {
  std::string s = kGood;
  s.replace(s.find(from), from.size(), to);
  return s;
}

}  // namespace

TEST_CASE("a valid scene compiles") { CHECK(test::scene_error(kGood).empty()); }

TEST_CASE("unknown key: location and suggestion") {
  const std::string e = test::scene_error(with("k_n = 1e5", "k_n = 1e5\nfriciton = 0.3"));
  CHECK(e.rfind("bad.toml:9:1: ", 0) == 0);
  CHECK(e.find("unknown key 'contact.friciton'") != std::string::npos);
  CHECK(e.find("did you mean 'contact.friction'") != std::string::npos);
  // Unknown table, and a key of a group table.
  const std::string t = test::scene_error(with("[run]", "[rnu]"));
  CHECK(t.rfind("bad.toml:12:", 0) == 0);
  CHECK(t.find("unknown key 'rnu") != std::string::npos);
  CHECK(t.find("did you mean 'run'") != std::string::npos);
  CHECK(test::scene_error(with("[contact]", "[contakt]")).find("did you mean 'contact'") != std::string::npos);
  const std::string g = test::scene_error(with("radius = 0.5", "raduis = 0.5"));
  CHECK(g.find("bad.toml:11:1") != std::string::npos);
  CHECK(g.find("did you mean 'grains[0].radius'") != std::string::npos);
  // Without an index, the first entry's (it suggested 'grains[].count', itself refused).
  CHECK(unknown_key_message("grains.count") == "unknown key 'grains.count'; did you mean 'grains[0].count'?");
  // A short leaf two edits from a key of another table is no suggestion.
  const std::string far = test::scene_error(with("k_n = 1e5", "k_n = 1e5\nnope = 1"));
  CHECK(far.find("unknown key 'contact.nope'") != std::string::npos);
  CHECK(far.find("did you mean") == std::string::npos);
  // Nor one edit from a 3-letter key of another table (it suggested 'render.camera.fov').
  const std::string foo = test::scene_error(with("k_n = 1e5", "k_n = 1e5\nfoo = 1"));
  CHECK(foo.find("unknown key 'contact.foo'") != std::string::npos);
  CHECK(foo.find("did you mean") == std::string::npos);
  CHECK(test::scene_error(with("k_n = 1e5", "k_n = 1e5\nmodle = 1")).find("did you mean 'contact.model'") !=
        std::string::npos);
}

TEST_CASE("a byte that is no UTF-8 is located at its own line and column") {
  // The parser's location was the end of the line before (34:10 for a bad byte at 35:1).
  const std::string at_line_start = test::scene_error(with("[run]", "\xff\xfe = 1\n[run]"));
  CHECK(at_line_start.rfind("bad.toml:12:1: ", 0) == 0);
  CHECK(at_line_start.find("invalid UTF-8 (byte 0xFF)") != std::string::npos);
  // In a comment after a character of two bytes: columns count characters.
  const std::string in_comment = test::scene_error(with("k_n = 1e5", "k_n = 1e5 # \xc3\xa9t\xe9"));
  CHECK(in_comment.rfind("bad.toml:8:15: ", 0) == 0);
  // Overlong forms and surrogates are not UTF-8 either; well-formed text of 2 to 4 bytes is.
  CHECK(first_invalid_utf8("a\xc0\xaf"
                           "b") == 1);
  CHECK(first_invalid_utf8("\xed\xa0\x80") == 0);
  CHECK(first_invalid_utf8("\xf4\x90\x80\x80") == 0);
  CHECK(first_invalid_utf8("\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80") == std::string::npos);
  CHECK(first_invalid_utf8("ok\xe2\x82") == 2);  // cut short
  CHECK(test::scene_error(with("k_n = 1e5", "k_n = 1e5 # \xc3\xa9\xe2\x82\xac")).empty());
}

TEST_CASE("wrong type: location of the value") {
  const std::string e = test::scene_error(with("k_n = 1e5", "k_n = \"stiff\""));
  CHECK(e.rfind("bad.toml:8:7: ", 0) == 0);
  CHECK(e.find("'contact.k_n' must be a number") != std::string::npos);
  CHECK(test::scene_error(with("count = 10", "count = 10.5")).find("'grains[0].count' must be an integer") !=
        std::string::npos);
}

TEST_CASE("out of range: the range and unit are named") {
  const std::string e = test::scene_error(with("k_n = 1e5", "k_n = -3"));
  CHECK(e.rfind("bad.toml:8:7: ", 0) == 0);
  CHECK(e.find("out of range > 0 N/m") != std::string::npos);
  CHECK(test::scene_error(with("dimension = 3", "dimension = 4")).find("[2, 3]") != std::string::npos);
  // An integer past int64's reach is past the key's range too (it read "must be an integer").
  CHECK(test::scene_error(with("dimension = 3", "dimension = 9223372036854775807")).find("is out of range [2, 3]") !=
        std::string::npos);
  // An integer is shown as given, not as its double (which read 9223372036854775808 and, past 2^53,
  // 9007199254740992 for 9007199254740993).
  for (const char* n : {"9223372036854775807", "9007199254740993", "-9223372036854775807"})
    CHECK(test::scene_error(with("dimension = 3", std::string("dimension = ") + n))
              .find(std::string("'scene.dimension' = ") + n + " is out of range") != std::string::npos);
  // Past int64 on the command line, where TOML reads no integer (it read "must be an integer").
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("scene.dimension=-9223372036854775809")}),
                       doctest::Contains("'scene.dimension' = -9223372036854775809 is out of range [2, 3] (and beyond "
                                         "the integers', 9223372036854775807 in magnitude)"),
                       SceneError);
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("fluid.cells=[16, 9007199254740993]")}),
                       doctest::Contains("'fluid.cells' = 9007199254740993 is out of range"), SceneError);
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("render.width=99999999999999999999")}),
                       doctest::Contains("is out of range [16, 16384] px (and beyond"), SceneError);
  // A control byte, in the key or the value, at its column (it went into a scene's name).
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("scene.name=ab\x01c")}),
                       "--set:1:14: control character", SceneError);
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("contact.fric\x7ftion=0.3")}),
                       "--set:1:13: control character", SceneError);
  CHECK(parse_scene(kGood, "bad.toml", {parse_override("scene.name=a\tb")}).string("scene.name") == "a\tb");
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("scene.dimension=007")}),
                       doctest::Contains("must be an integer"), SceneError);
  // Past the doubles' range TOML reads no value: said, at the number's first column (it read "could
  // not be interpreted as a value", one column past its end), and on the command line (it read
  // "must be a number").
  const std::string past = test::scene_error(with("k_n = 1e5", "k_n = 1e309"));
  CHECK(past.rfind("bad.toml:8:7: 1e309 is beyond 1e308", 0) == 0);
  try {
    (void)parse_scene(kGood, "good.toml", {Override{"contact.k_n", "1e400"}});
    FAIL("accepted");
  } catch (const SceneError& err) {
    CHECK(std::string(err.what()).find("'contact.k_n' = 1e400 is beyond 1e308") != std::string::npos);
  }
  // Past 1e308 the key's own range is not the reason (it read "is out of range any").
  CHECK(test::scene_error(with("k_n = 1e5", "k_n = 1.5e308")).find("k_n' = 1.5e+308 is beyond 1e308") !=
        std::string::npos);
  // Below the doubles' range TOML reads 0, which turns some keys off: said where it is written, in
  // a list too; a denormal is a number, and a zero written small is 0.
  CHECK(test::scene_error(with("k_n = 1e5", "k_n = 1e-400")).rfind("bad.toml:8:7: 1e-400 is below 4.9e-324", 0) == 0);
  CHECK(test::scene_error(with("k_n = 1e5", "k_n = 1e5\nfriction = 1_0.5e-401"))
            .rfind("bad.toml:9:12: 1_0.5e-401 is below 4.9e-324", 0) == 0);
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("domain.hi=[1.0, 2.5e-999]")}),
                       doctest::Contains("2.5e-999 is below 4.9e-324"), SceneError);
  CHECK(test::scene_error(with("k_n = 1e5", "k_n = 1e-320")).find("below") == std::string::npos);
  CHECK(test::scene_error(with("k_n = 1e5", "k_n = 0.0e-400")).find("below") == std::string::npos);
  const std::string c = test::scene_error(with("model = \"hooke\"", "model = \"hookean\""));
  CHECK(c.find("bad.toml:7:9") != std::string::npos);
  CHECK(c.find("is not one of: spring_dashpot hooke hertz linear") != std::string::npos);
}

TEST_CASE("TOML syntax errors keep their location") {
  const std::string e = test::scene_error(with("k_n = 1e5", "k_n = = 1e5"));
  CHECK(e.rfind("bad.toml:8:", 0) == 0);
}

TEST_CASE("values that do not apply are refused, not ignored") {
  const std::string e = test::scene_error(with("k_n = 1e5", "k_n = 1e5\nrestitution = 0.5"));
  CHECK(e.rfind("bad.toml:9:15: ", 0) == 0);
  CHECK(e.find("not used") != std::string::npos);
  // A 3D camera's keys in a 2D scene (they changed no pixel).
  std::string flat = with("dimension = 3", "dimension = 2");
  flat = flat.substr(0, flat.find("[domain]")) +
         "[domain]\nlo = [0, 0]\nhi = [10, 10]\n[render]\ncamera.azimuth = 10.0\n" +
         flat.substr(flat.find("[contact]"));
  const std::string camera = test::scene_error(flat);
  CHECK(camera.find("render.camera.azimuth applies to 3D scenes only") != std::string::npos);
}

TEST_CASE("scenes that cannot be simulated are refused before the first step") {
  // A time step above the stability limit names the parameter.
  const std::string dt = test::scene_error(with("dt = 1e-4", "dt = 0.1"));
  CHECK(dt.find("bad.toml:13:6") != std::string::npos);
  CHECK(dt.find("stability limit") != std::string::npos);
  CHECK(dt.find("reduce run.dt") != std::string::npos);
  // Too many grains for random placement.
  CHECK(test::scene_error(with("count = 10", "count = 5000")).find("could not place") != std::string::npos);
  // Wrong vector length.
  CHECK(test::scene_error(with("lo = [0, 0, 0]", "lo = [0, 0]")).find("needs 3 entries") != std::string::npos);
  // Overlapping explicit grains.
  const std::string ov = test::scene_error(
      with("count = 10\nradius = 0.5", "radius = 0.5\nplacement = \"explicit\"\npositions = [[1, 1, 1], [1.2, 1, 1]]"));
  CHECK(ov.find("overlap by") != std::string::npos);
  CHECK(ov.rfind("bad.toml:12:13: ", 0) == 0);  // at the positions of the group
  // Unknown observable with a suggestion.
  const std::string ob = test::scene_error(with("[run]", "[output]\nobserve = [\"t\", \"kee\"]\n[run]"));
  CHECK(ob.find("unknown observable 'kee'; did you mean 'ke'") != std::string::npos);
  // A name of a 3D scene in a 2D one (it was "unknown", though documented).
  const Model disks = test::model_from(test::frictional_gas(2, 0.0, 0.0, 0.06));
  for (const char* name : {"stress.zz", "p[0].z", "momentum.z"})
    CHECK(check_observable(name, disks).find("is of a 3D scene, and this one is 2D") != std::string::npos);
}

TEST_CASE("--set overrides: typed, located, and checked like the file") {
  SceneDesc d =
      parse_scene(kGood, "bad.toml", {parse_override("contact.friction=0.25"), parse_override("grains.0.count=12")});
  CHECK(d.real("contact.friction") == 0.25);
  CHECK(d.integer("grains[0].count") == 12);
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("contact.friciton=0.25")}),
                       doctest::Contains("did you mean 'contact.friction'"), SceneError);
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("contact.friction=-1")}),
                       doctest::Contains("--set:1:"), SceneError);
  CHECK_THROWS_AS(parse_scene(kGood, "bad.toml", {parse_override("grains.3.count=2")}), SceneError);
  for (const char* zeros : {"grains.00.count=2", "grains[00].count=2", "grains[0000000000].count=2"})
    CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override(zeros)}),
                         doctest::Contains("write the index of grains[...] without leading zeros (grains[0])"),
                         SceneError);
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("grains[1234567890].count=2")}),
                       doctest::Contains("no grains[1234567890] in the scene (it has 1)"), SceneError);
  CHECK_THROWS_WITH_AS(parse_scene(std::string("gravity = 1\n") + kGood, "bad.toml"),
                       doctest::Contains("bad.toml:1:1: 'gravity' is a table, not a key: its keys are gravity."),
                       SceneError);
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("contact=1")}),
                       doctest::Contains("'contact' is a table, not a key: its keys are contact."), SceneError);
  SceneDesc s = parse_scene(kGood, "bad.toml", {parse_override("contact.model=hertz")});
  CHECK(s.string("contact.model") == "hertz");
  // A list of strings takes bare words as items, as a bare word is a string on its own
  // (render.draw=[grains] was "Error while parsing boolean: expected 'false', saw 'gr'").
  for (const char* list :
       {"render.draw=[grains, chains]", "render.draw=[ grains,\"chains\", ]", "render.draw=['grains' , chains]"}) {
    CAPTURE(list);
    CHECK(parse_scene(kGood, "bad.toml", {parse_override(list)}).strings("render.draw") ==
          std::vector<std::string>{"grains", "chains"});
  }
  for (const char* list : {"render.draw=[grains, [chains]]", "render.draw=[,]", "render.draw=[grains,,chains]",
                           "render.draw=[grains # x]", "render.draw=[\"grains, chains]"}) {
    CAPTURE(list);
    CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override(list)}),
                         doctest::Contains("cannot read the value of render.draw"), SceneError);
  }
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("render.draw=[grains, chain]")}),
                       doctest::Contains("'render.draw' = \"chain\" is not one of"), SceneError);
  // (a list of numbers keeps TOML's reading: a bare word there is no number)
  CHECK_THROWS_WITH_AS(parse_scene(kGood, "bad.toml", {parse_override("domain.hi=[a, 1, 1]")}),
                       doctest::Contains("cannot read the value of domain.hi"), SceneError);
}

TEST_CASE("the schema is consistent") {
  for (const KeySpec& k : scene_schema()) {
    CAPTURE(k.path);
    CHECK(!k.doc.empty());
    if (k.def && (k.type == KeyType::kReal)) CHECK(k.range.contains(std::get<double>(*k.def)));
    CHECK(find_key_spec(k.path) == &k);
  }
  CHECK(schema_markdown().find("| `contact.friction` |") != std::string::npos);
}

TEST_CASE("a missing key, or none of its alternatives, is reported where it belongs") {
  // Inside its table: at the table's header.
  const std::string hi = test::scene_error(with("hi = [10, 10, 10]\n", ""));
  CHECK(hi.rfind("bad.toml:3:1: missing required key 'domain.hi'", 0) == 0);
  const std::string radius = test::scene_error(with("radius = 0.5\n", ""));
  CHECK(radius.rfind("bad.toml:9:1: grains[0] needs exactly one of radius", 0) == 0);
  // Without its table: at the start of the file.
  CHECK(test::scene_error(with("[[grains]]\ncount = 10\nradius = 0.5\n", "")).rfind("bad.toml:1:1: ", 0) == 0);
}

TEST_CASE("a wall normal of any length is a direction: 1e200 and 1e-300 along y give the wall along y") {
  // Its norm was taken from its squares: [0, 1e200, 0] became a wall of normal (0, inf, 0), whose
  // one grain read an overlap of 100 % 4.5 radii above it; [0, 1e-300, 0] was "zero".
  for (const char* n : {"[0, 1, 0]", "[0, 1e200, 0]", "[0, 1e-300, 0]", "[0, 3e-310, 0]"}) {
    CAPTURE(n);
    const Model m = test::model_from(std::string(kGood) + "[[walls]]\npoint = [0, 0, 0]\nnormal = " + n + "\n");
    REQUIRE(m.walls.size() == 1);
    CHECK(m.walls[0].normal[0] == 0);
    CHECK(m.walls[0].normal[1] == 1);
    CHECK(m.walls[0].normal[2] == 0);
  }
  const Model m = test::model_from(std::string(kGood) + "[[walls]]\npoint = [0, 0, 0]\nnormal = [0, 3e200, 4e200]\n");
  CHECK(m.walls[0].normal[1] == doctest::Approx(0.6));
  CHECK(m.walls[0].normal[2] == doctest::Approx(0.8));
  CHECK(test::scene_error(std::string(kGood) + "[[walls]]\npoint = [0, 0, 0]\nnormal = [0, 0, 0]\n").find("zero") !=
        std::string::npos);
}

TEST_CASE("a wall whose normal points out of the domain is refused at its normal") {
  // All of the domain behind it: random placement said "could not place grain 1 at random", a
  // lattice "grain 0 overlaps wall 0".
  const std::string wall = std::string(kGood) + "[[walls]]\npoint = [0, 0, 0]\nnormal = [0, -1, 0]\n";
  const std::string e = test::scene_error(wall);
  CHECK(e.rfind("bad.toml:16:10: ", 0) == 0);
  CHECK(e.find("points out of the domain") != std::string::npos);
  // A wall at the far face facing in, and one inside the domain facing out of its part, are fine.
  CHECK(test::scene_error(std::string(kGood) + "[[walls]]\npoint = [0, 10, 0]\nnormal = [0, -1, 0]\n").empty());
  CHECK(test::scene_error(std::string(kGood) + "[[walls]]\npoint = [0, -5, 0]\nnormal = [0, 1, 1]\n").empty());
  // On the far face facing out: nothing of the domain in front of it.
  CHECK(test::scene_error(std::string(kGood) + "[[walls]]\npoint = [0, 10, 0]\nnormal = [0, 1, 0]\n")
            .find("points out of the domain") != std::string::npos);
}

TEST_CASE("random placement that the walls leave no room for names the wall, not the packing fraction") {
  // The region (here the domain) reaches past a wall at x = 0.6 facing -x: every position of a grain
  // of radius 0.5 is behind it. It said the group "fills 0.052 of its region".
  const std::string e = test::scene_error(std::string(kGood) + "[[walls]]\npoint = [0.6, 0, 0]\nnormal = [-1, 0, 0]\n");
  CHECK(e.find("20000 of 20000 random positions") != std::string::npos);
  CHECK(e.find("behind walls[0]") != std::string::npos);
  // Two walls facing each other closer than a diameter: each refuses part of the positions, and
  // both are named (the one that refused more was named alone, and neither when both refused
  // under half).
  const std::string two = test::scene_error(std::string(kGood) +
                                            "[[walls]]\npoint = [4, 0, 0]\nnormal = [1, 0, 0]\n"
                                            "[[walls]]\npoint = [4.8, 0, 0]\nnormal = [-1, 0, 0]\n");
  CHECK(two.find("20000 of 20000 random positions") != std::string::npos);
  CHECK(two.find(" behind walls[0], ") != std::string::npos);
  CHECK(two.find(" behind walls[1]);") != std::string::npos);
  // Too many grains for the room between the walls is still the packing's message.
  const std::string full = test::scene_error(with("count = 10", "count = 5000"));
  CHECK(full.find("random addition jams") != std::string::npos);
}
