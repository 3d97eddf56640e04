// medspheres: bake, evaluate and inspect medial sphere sets from the shell.
#include <exception>
#include <iostream>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "cli_common.h"
#include "medspheres/error.h"
#include "medspheres/version.h"

int main(int argc, char** argv) {
  using namespace medspheres::cli;
  CLI::App app{"medspheres " MEDSPHERES_VERSION_STRING
               ": approximate a triangle-mesh solid with medial spheres"};
  app.require_subcommand(1);
  app.set_version_flag("--version", MEDSPHERES_VERSION_STRING);

  Runner info = register_info(app);
  Runner bake = register_bake(app);
  Runner eval = register_eval(app);
  Runner convert = register_convert(app);
  Runner robot = register_robot(app);
  Runner render = register_render(app);
  Runner view = register_view(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the message and the usage hint
    return kExitBadInput;
  }

  try {
    for (CLI::App* sub : app.get_subcommands()) {
      if (sub->get_name() == "info") return info();
      if (sub->get_name() == "bake") return bake();
      if (sub->get_name() == "eval") return eval();
      if (sub->get_name() == "convert") return convert();
      if (sub->get_name() == "robot") return robot();
      if (sub->get_name() == "render") return render();
      if (sub->get_name() == "view") return view();
    }
    std::cerr << "medspheres: error: no subcommand given\n";
    return kExitBadInput;
  } catch (const medspheres::InputError& e) {
    return report_input_error(e);
  } catch (const std::invalid_argument& e) {
    std::cerr << "medspheres: error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "medspheres: failure: " << e.what() << "\n";
    return kExitFailure;
  }
}
