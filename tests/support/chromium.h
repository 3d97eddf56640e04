#pragma once
// Headless Chromium for the viewer page: where it is, and the command line that loads a
// page from disk with software WebGL (the browser test and bench_view_page).

#include <string>

#include "support/run_command.h"

namespace medspheres::test {

/// The first of chromium, chromium-browser, google-chrome on PATH; "" when none is.
inline std::string find_chromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    const CommandResult r = run_command(std::string("command -v ") + name);
    if (r.exit_code == 0 && !r.out.empty()) return r.out.substr(0, r.out.find('\n'));
  }
  return {};
}

/// Headless with software WebGL (SwiftShader through ANGLE); --no-sandbox because CI runs
/// as root; \p args follow (the page, what to dump). \p virtual_time_ms > 0 lets the page's
/// module scripts run in virtual time before the dump (the test); 0 runs in real time (the
/// benchmark: the page's scripts run before the load event, the dump after it).
inline std::string chromium_command(const std::string& chromium, const std::string& args,
                                    int virtual_time_ms = 20000) {
  return "timeout 120 " + shell_quote(chromium) +
         " --headless --no-sandbox --disable-dev-shm-usage --use-angle=swiftshader"
         " --enable-unsafe-swiftshader --use-gl=angle --no-first-run --disable-extensions"
         " --hide-scrollbars " +
         (virtual_time_ms > 0 ? "--virtual-time-budget=" + std::to_string(virtual_time_ms) + " "
                              : std::string()) +
         args;
}

}  // namespace medspheres::test
