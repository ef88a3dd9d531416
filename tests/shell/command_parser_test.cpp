// The shell's command language: words, quotes, comments, arity, run lengths, conditions.
#include <doctest/doctest.h>

#include "shell/command_parser.hpp"

using namespace silt::shell;

TEST_CASE("lines split into a command and its words") {
  CHECK_FALSE(parse_line("").has_value());
  CHECK_FALSE(parse_line("   # only a comment").has_value());
  const auto c = parse_line("  set contact.friction 0.3   # steer");
  REQUIRE(c);
  CHECK(c->name == "set");
  CHECK(c->name_col == 3);
  REQUIRE(c->args.size() == 2);
  CHECK(c->args[0].text == "contact.friction");
  CHECK(c->args[0].col == 7);
  CHECK(c->args[1].text == "0.3");
  const auto q = parse_line(R"(load "my scenes/a \"b\".toml" x)");
  REQUIRE(q);
  CHECK(q->args[0].text == R"(my scenes/a "b".toml)");
  CHECK(q->args[1].text == "x");
  CHECK(parse_line("render \"\"")->args[0].text.empty());
}

TEST_CASE("malformed lines: the column and the reason") {
  auto col_of = [](const char* line) {
    try {
      parse_line(line);
    } catch (const ParseError& e) {
      return e.col;
    }
    return -1;
  };
  CHECK(col_of("load \"a.toml") == 6);  // unterminated quote
  CHECK(col_of("load \"a\"b") == 9);    // no blank after a quoted word
  CHECK(col_of("load a\"b") == 7);      // quote inside a word
  CHECK(col_of("print t\x01") == 8);    // control character
  CHECK(col_of("print t # \"") == -1);  // quotes in comments are fine
}

TEST_CASE("commands are checked: unknown names with a suggestion, wrong argument counts") {
  CHECK(check_command(*parse_line("run 10")).name == "run");
  CHECK(check_command(*parse_line("exit")).name == "quit");
  CHECK_THROWS_WITH_AS(check_command(*parse_line("rnu 10")), doctest::Contains("did you mean 'run'"), ParseError);
  CHECK_THROWS_WITH_AS(check_command(*parse_line("set a")), doctest::Contains("usage: set KEY VALUE"), ParseError);
  try {
    check_command(*parse_line("load a b"));
  } catch (const ParseError& e) {
    CHECK(e.col == 8);  // the extra word
  }
  CHECK(suggest_command("prnt") == "print");
  CHECK(suggest_command("zzzzzzz").empty());
  for (const CommandSpec& s : command_specs()) {
    CHECK(!s.help.empty());
    CHECK(find_command(s.name) == &s);
  }
}

TEST_CASE("run lengths: steps, simulated time, conditions") {
  auto len = [](const char* line) { return parse_run_length(parse_line(line)->args); };
  CHECK(len("run 1000").kind == RunLength::kSteps);
  CHECK(len("run 1000").steps == 1000);
  CHECK(len("run 1e3").steps == 1000);
  CHECK(len("run 0.5s").kind == RunLength::kTime);
  CHECK(len("run 0.5s").time == 0.5);
  const RunLength u = len("run until t >= 1 and ke < 1e-6 or step == 5");
  REQUIRE(u.kind == RunLength::kUntil);
  REQUIRE(u.until.clauses.size() == 3);
  CHECK(u.until.clauses[1].observable == "ke");
  CHECK(u.until.clauses[1].op == "<");
  CHECK(u.until.clauses[1].value == 1e-6);
  // (t >= 1 and ke < 1e-6) or step == 5, left to right.
  CHECK(u.until.holds({2, 0, 0}));
  CHECK_FALSE(u.until.holds({2, 1, 0}));
  CHECK(u.until.holds({0, 1, 5}));
  // "and" binds tighter than "or": a or (b and c), not (a or b) and c.
  const RunLength p = len("run until step >= 60 or t < 0 and dt < 0");
  CHECK(p.until.holds({60, 1, 1}));
  CHECK_FALSE(p.until.holds({59, 1, -1}));
  CHECK(p.until.holds({0, -1, -1}));
  const RunLength q = len("run until t < 0 and dt < 0 or step >= 60 and ke < 1");
  CHECK(q.until.holds({1, 1, 60, 0}));
  CHECK_FALSE(q.until.holds({1, 1, 60, 2}));
  CHECK(q.until.holds({-1, -1, 0, 2}));
  for (const char* bad : {"run -3", "run 1.5", "run abc", "run 0s", "run xs", "run 10 20", "run until t",
                          "run until t >= x", "run until t => 1", "run until t > 1 and", "run until t > 1 but x < 2"})
    CHECK_THROWS_AS(len(bad), ParseError);
}

TEST_CASE("numbers are read whole") {
  CHECK(parse_number("2.5") == 2.5);
  CHECK(parse_number("-1e-3") == -1e-3);
  CHECK_FALSE(parse_number("2.5x").has_value());
  CHECK_FALSE(parse_number("").has_value());
  CHECK_FALSE(parse_number("nan").has_value());
  CHECK_FALSE(parse_number("1e999").has_value());
}

TEST_CASE("lists are one word, written as on the command line, and expand into their items") {
  const auto c = parse_line(R"(render a.png ["grains", "chains"] box)");
  REQUIRE(c);
  REQUIRE(c->args.size() == 3);
  CHECK(c->args[1].text == R"(["grains", "chains"])");
  CHECK(c->args[1].col == 14);
  const auto items = expand_lists(c->args, 1);
  REQUIRE(items.size() == 4);
  CHECK(items[1].text == "grains");
  CHECK(items[1].col == 15);
  CHECK(items[2].text == "chains");
  CHECK(items[3].text == "box");
  CHECK(expand_list(Token{"[t,step]", 1, ""}).size() == 2);
  CHECK(expand_list(Token{"[]", 1, ""}).empty());
  CHECK(expand_list(Token{"p[3].vx", 1, ""})[0].text == "p[3].vx");  // not a list: it does not start with [
  CHECK_THROWS_AS(parse_line("set render.draw [\"grains\""), ParseError);
  CHECK_THROWS_AS(expand_list(Token{"[a,,b]", 1, ""}), ParseError);
  CHECK_THROWS_AS(expand_list(Token{"[a b]", 1, ""}), ParseError);
}

TEST_CASE("an inline table is one word, and a bracket inside either quote does not end a list or a table") {
  const auto c = parse_line(R"(set scene.name {a = 1, b = "}"} x ['a]b', "c]"])");
  REQUIRE(c);
  REQUIRE(c->args.size() == 4);
  CHECK(c->args[1].text == R"({a = 1, b = "}"})");
  CHECK(c->args[2].text == "x");
  CHECK(c->args[3].text == R"(['a]b', "c]"])");
  CHECK(c->args[3].col == 35);
  CHECK_THROWS_WITH_AS(parse_line("set scene.name {a = 1"), "a table without its closing }", ParseError);
  CHECK_THROWS_WITH_AS(parse_line("set scene.name {a = 1}x"), "a table must be followed by a blank", ParseError);
  CHECK_THROWS_WITH_AS(parse_line("set x ['a]"), "unterminated quote", ParseError);
}

TEST_CASE("a list's brackets match, a '#' inside it is refused where it stands, and its tabs are blanks") {
  const auto at = [](const std::string& line) {
    try {
      parse_line(line);
    } catch (const ParseError& e) {
      return std::to_string(e.col) + ": " + e.what();
    }
    return std::string("accepted");
  };
  CHECK(at("set fluid.cells [32, 32}") == "24: a '}' closes a '['");
  CHECK(at("set x {a = [1, 2}}") == "17: a '}' closes a '['");
  CHECK(at("set x [{a = 1]]") == "14: a ']' closes a '{'");
  CHECK(at("set render.draw [\"field\" # c]") ==
        "26: a '#' inside a list or table (quote it: a '#' starts a "
        "comment)");
  CHECK(at("set render.draw [\"field\"] # c") == "accepted");
  CHECK(parse_line("set x [\"a#b\", 'c#']")->args[1].text == "[\"a#b\", 'c#']");
  const auto tabs = parse_line("set fluid.cells [32,\t32] scene.name [\"a\tb\"]");
  CHECK(tabs->args[1].text == "[32, 32]");
  CHECK(tabs->args[3].text == "[\"a\tb\"]");  // inside quotes a tab is the string's
  CHECK(shown_word(tabs->args[1].text) == "[32, 32]");
  CHECK(at("set render.draw [\"field\", 'time") == "27: unterminated quote");  // at the quote, not the list
  CHECK(at("print [\"t\x7f\"]") == "10: control character");
  CHECK(at("print [\"t\\\x01\"]") == "11: control character");               // after a backslash too
  const auto single = expand_list(Token{"['t', \"step\", 'a\\b']", 7, ""});  // 'single' items as TOML reads them
  REQUIRE(single.size() == 3);
  CHECK(single[0].text == "t");
  CHECK(single[1].text == "step");
  CHECK(single[2].text == "a\\b");
  CHECK(expand_list(parse_line("print \"[t, step]\"")->args[0]).size() == 1);  // quoted: one word, not a list
  CHECK(at("print \"a\x01b\"") == "9: control character");
  CHECK(at("print st\x7f"
           "ep") == "9: control character");
  CHECK(at("print 'st\x7f'") == "10: control character");
  CHECK(expand_list(Token{"[t, step, ]", 1, ""}).size() == 2);  // a trailing comma, as TOML and set allow
  CHECK_THROWS_AS(expand_list(Token{"[t, , ]", 1, ""}), ParseError);
  CHECK_THROWS_AS(expand_list(Token{"[,]", 1, ""}), ParseError);
  CHECK(at("run until [step >= 1]") == "accepted");
  CHECK_THROWS_WITH_AS(parse_run_length(parse_line("run until [step >= 1]")->args),
                       "no brackets in a condition: OBSERVABLE OP NUMBER (t >= 0.5)", ParseError);
}

TEST_CASE("a window of t is open while its term's clauses on t and step hold, for adaptive steps") {
  const auto cond = [](const std::string& line) { return parse_run_length(parse_line(line)->args).until; };
  const Condition c = cond("run until t >= 0.0207 and t <= 0.0255 and phi > 0 or ke < 0");
  CHECK(c.time_window_open(0.0208, 9));
  CHECK_FALSE(c.time_window_open(0.0200, 8));
  CHECK_FALSE(c.time_window_open(0.0260, 10));
  CHECK_FALSE(cond("run until t >= 0.02 and phi > 0").time_window_open(0.03, 9));  // not bounded above
  CHECK_FALSE(cond("run until step <= 9 and phi > 0").time_window_open(0.03, 9));  // steps are foretold
}

TEST_CASE("run until takes t within its rounding of a value to be at it") {
  const auto cond = [](const std::string& line) { return parse_run_length(parse_line(line)->args).until; };
  const double t = 3 * 1e-4;  // 3.0000000000000003e-4, shown as 0.0003
  REQUIRE(t != 0.0003);
  CHECK(cond("run until t <= 0.0003").holds({t}));
  CHECK(cond("run until t == 0.0003").holds({t}));
  CHECK(cond("run until t >= 0.0003").holds({t}));
  CHECK_FALSE(cond("run until t < 0.0003").holds({t}));
  CHECK_FALSE(cond("run until t > 0.0003").holds({t}));
  CHECK_FALSE(cond("run until t != 0.0003").holds({t}));
  CHECK_FALSE(cond("run until t <= 0.0003").holds({0.0003 * (1 + 1e-8)}));  // past the rounding: not at it
  CHECK_FALSE(cond("run until step == 3").holds({3 + 1e-12}));              // a step count is exact
}

TEST_CASE("a term is tested between regular tests where its window of t and step closes before the next") {
  const auto cond = [](const std::string& line) { return parse_run_length(parse_line(line)->args).until; };
  const Condition c = cond("run until step == 7 and ke < 1 or z > 5");
  CHECK(c.has_window());
  CHECK(c.window_closes(0.1, 7, 0.01, 3));
  CHECK_FALSE(c.window_closes(0.1, 8, 0.01, 2));  // the other observables need not be sampled at step 8
  const Condition w = cond("run until step > 56 and step < 58 and ke > 0");  // a window of one step
  CHECK(w.window_closes(0, 57, 1, 3));
  CHECK_FALSE(w.window_closes(0, 55, 1, 5));
  const Condition d = cond("run until z > 5 or t < 1 and ke < 1e-3");
  CHECK_FALSE(d.window_closes(0.5, 50, 0.01, 10));  // open at the next test: that test will do
  CHECK(d.window_closes(0.95, 95, 0.01, 5));
  CHECK_FALSE(cond("run until step >= 7 or ke < 1").has_window());  // no window closes
}

TEST_CASE("a malformed condition is blamed at the word that is wrong, or the one a missing word follows") {
  const auto error = [](const std::string& line) -> std::pair<int, std::string> {
    try {
      parse_run_length(parse_line(line)->args);
    } catch (const ParseError& e) {
      return {e.col, e.what()};
    }
    return {0, ""};
  };
  using E = std::pair<int, std::string>;
  CHECK(error("run until ke") == E{11, "a comparison after 'ke' (< <= > >= == !=)"});
  CHECK(error("run until ke <") == E{14, "a number after '<'"});
  CHECK(error("run until ke 5") == E{14, "'5' is not a comparison (< <= > >= == !=)"});
  CHECK(error("run until < 5") == E{11, "'<' where an observable was expected (OBSERVABLE OP NUMBER, e.g. t >= 0.5)"});
  // (the second 'or' was read as an observable, and 't' blamed as not a comparison)
  CHECK(error("run until ke < 5 or or t > 1").first == 21);
  CHECK(error("run until ke<5 and >3").first == 20);
  CHECK(error("run until ke < 5 xor t > 1") == E{18, "'xor' where 'and' or 'or' was expected"});
  CHECK(error("run until ke < 5 and") == E{18, "a condition after 'and'"});
  CHECK(error("run until k\xc3\xa9 < 5 or x").first == 21);  // columns count characters, not bytes
  CHECK(error("run until 1 >= t") == E{11, "'1' where an observable was expected: OBSERVABLE OP NUMBER (t >= 0.5)"});
  CHECK(error("run until (t >= 1)") == E{11, "no parentheses in a condition: 'and' binds tighter than 'or'"});
}

TEST_CASE("a condition needs no blanks around its comparisons, and until static and until steady parse") {
  const auto c = parse_line("run until t>=30 and ke<1e-3");
  REQUIRE(c);
  const RunLength r = parse_run_length(c->args);
  REQUIRE(r.kind == RunLength::kUntil);
  REQUIRE(r.until.clauses.size() == 2);
  CHECK(r.until.clauses[0].observable == "t");
  CHECK(r.until.clauses[0].op == ">=");
  CHECK(r.until.clauses[0].value == 30);
  CHECK(r.until.clauses[1].op == "<");
  CHECK(r.until.clauses[1].value == doctest::Approx(1e-3));
  CHECK(parse_run_length(parse_line("run until x!=-2")->args).until.clauses[0].value == -2);
  CHECK(parse_run_length(parse_line("run until static")->args).kind == RunLength::kStatic);
  CHECK(parse_run_length(parse_line("run until steady")->args).kind == RunLength::kSteady);
  CHECK_THROWS_AS(parse_run_length(parse_line("run until t>=")->args), ParseError);
  CHECK_THROWS_AS(parse_run_length(parse_line("run until t=>1")->args), ParseError);
}

TEST_CASE("shown_word: a typed word as a message shows it, quoted where it would not read back as one word") {
  CHECK(shown_word("0.3") == "0.3");
  CHECK(shown_word("[0, 0, -1]") == "[0, 0, -1]");  // a list is one word with its blanks
  CHECK(shown_word("[\"t\", \"ke\"]") == "[\"t\", \"ke\"]");
  CHECK(shown_word("x y") == "\"x y\"");
  CHECK(shown_word("") == "\"\"");
  CHECK(shown_word("a\"b") == "\"a\\\"b\"");
  CHECK(shown_word("#1") == "\"#1\"");
  CHECK(shown_word("a\tb") == "\"a?b\"");
  // What it shows reads back as the word (control bytes apart)
  for (const char* w : {"x y", "a\"b", "c:\\d", "#1", "it's"}) {
    const auto c = parse_line("set k " + shown_word(w));
    REQUIRE(c);
    REQUIRE(c->args.size() == 2);
    CHECK(c->args[1].text == w);
  }
}
