// `silt`: command-line entry point. Usage errors exit 1, scene errors 2, numerical failures 3,
// I/O errors 4 (INTERFACE.md).
#include <CLI/CLI.hpp>
#include <iostream>

#include "shell/cli_options.hpp"
#include "shell/commands.hpp"
#include "shell/escaped_output.hpp"
#include "silt/scene.hpp"

int main(int argc, char** argv) {
  using namespace silt::cli;
  // (a file name holding ESC or BEL was echoed raw in a message, acting on the terminal)
  const EscapedOutput out(std::cout), err(std::cerr);
  CLI::App app{"silt: dense granular matter in a viscous fluid"};
  app.set_version_flag("--version", std::string("silt ") + SILT_VERSION);
  app.require_subcommand(1);
  const std::string codes =
      "\nExit codes: 0 success, 1 usage error, 2 scene or script error (FILE:LINE:COL: message), 3 numerical "
      "failure (the step, the stage and the parameter to change; the last good state kept), 4 I/O error.";
  app.footer(codes);

  RunArgs run;
  auto* r = app.add_subcommand("run", "Run a scene headless (the main job)");
  r->footer(codes);
  r->add_option("scene", run.scene, "Scene file (TOML)")->required();
  r->add_option("--set", run.sets, "Override a scene value: KEY=VALUE (dotted TOML path); repeatable")
      ->check(key_value());
  auto* steps =
      r->add_option("--steps", run.steps,
                    "Run length in steps, from the restored state with --restore (overrides [run], whose steps and "
                    "time are where the scene ends): 1000, 1e3")
          ->transform(whole_number(0));
  r->add_option("--time", run.time,
                "Run length in simulated seconds, from the restored state with --restore (overrides [run]): 0.5, 0.5s")
      ->excludes(steps)
      ->transform(seconds());
  r->add_option("--threads", run.threads, "Worker threads (default: all cores; 1 = serial reference)")
      ->transform(whole_number(1, kMaxThreads));
  r->add_option("--stats", run.stats, "Time series of observables (CSV)")->check(path_given());
  r->add_option("--observe", run.observe, "Comma-separated observables (default: the scene's [output] list)")
      ->check(observable_list());
  r->add_option("--every", run.every, "Sample every N steps (default: the scene's)")->transform(whole_number(1));
  r->add_option("--summary", run.summary, "Summary JSON written at the end")->check(path_given());
  r->add_option("--average-from", run.average_from, "Means and errors over samples with t >= T: 40, 40s")
      ->transform(seconds());
  r->add_flag("--quiet", run.quiet, "No progress line");
  auto* frames = r->add_option("--frames", run.frames,
                               "Write PNG frames DIR/frame_000000.png, ... (the scene's [render] settings)")
                     ->check(path_given());
  // (an interval without its output was ignored without a word)
  r->add_option("--frame-every", run.frame_every,
                "One frame every N steps (default: render.every, else --every, else output.every)")
      ->transform(whole_number(1))
      ->needs(frames);
  auto* vtk =
      r->add_option(
           "--vtk", run.vtk,
           "Write VTK files for ParaView/OVITO to DIR (grains .vtu, contacts .vtp, fluid fields .vti, index.pvd)")
          ->check(path_given());
  r->add_option("--vtk-every", run.vtk_every, "VTK files every N steps (default: --every, else output.every)")
      ->transform(whole_number(1))
      ->needs(vtk);
  r->add_option("--restore", run.restore,
                "Start from a checkpoint of the same grains (a prepared packing, a .last_good.ckpt)")
      ->check(path_given());
  r->add_option("--save", run.save, "Checkpoint of the final state (written atomically)")->check(path_given());

  CheckArgs check;
  auto* c = app.add_subcommand("check", "Validate a scene and print the compiled model");
  c->footer(codes);
  c->add_option("scene", check.scene, "Scene file (TOML)")->required();
  c->add_option("--set", check.sets, "Override a scene value: KEY=VALUE; repeatable")->check(key_value());
  c->add_option("--threads", check.threads, "Threads used to build the neighbour list")
      ->transform(whole_number(1, kMaxThreads));

  std::string shell_scene;
  int shell_threads = 0;
  auto* sh = app.add_subcommand("shell", "Interactive shell: load, run, steer, render, save");
  sh->footer(codes);
  sh->add_option("scene", shell_scene, "Scene file to load first");
  sh->add_option("--threads", shell_threads, "Worker threads (default: all cores)")
      ->transform(whole_number(1, kMaxThreads));

  std::string script;
  bool keep_going = false;
  int play_threads = 0;
  auto* pl = app.add_subcommand("play", "Play a script of shell commands, non-interactively");
  pl->footer(codes);
  pl->add_option("script", script, "Script (.silt): one command per line, # comments")->required();
  pl->add_flag("--keep-going", keep_going, "Go on after an error (at the end, the highest exit code of its errors)");
  pl->add_option("--threads", play_threads, "Worker threads (default: all cores)")
      ->transform(whole_number(1, kMaxThreads));

  bool markdown = false;
  auto* p = app.add_subcommand("params", "List every scene key with type, default, range and unit");
  p->add_flag("--markdown", markdown, "As a Markdown table");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // (it said "A subcommand is required")
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands({})) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || (argc > 1 && sub->get_name() == argv[1]);
    }
    if (argc > 1 && argv[1][0] != '-' && !known) {
      std::cerr << "silt: unknown command '" << argv[1] << "': one of " << names << " (silt --help)\n";
      return 1;
    }
    const int code = app.exit(e);
    return code == 0 ? 0 : 1;
  }
  try {
    if (r->parsed()) {
      run.threads = granted_threads(run.threads);
      return run_command(run);
    }
    if (c->parsed()) {
      check.threads = granted_threads(check.threads);
      return check_command(check);
    }
    if (sh->parsed()) return shell_command(shell_scene, granted_threads(shell_threads));
    if (pl->parsed()) return play_command(script, keep_going, granted_threads(play_threads));
    if (p->parsed()) {
      std::cout << (markdown ? silt::schema_markdown() : silt::schema_text());
      return 0;
    }
  } catch (const std::exception& e) {
    return report_error(std::string("internal error: ") + e.what(), 1);
  }
  return 1;
}
