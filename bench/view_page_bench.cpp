// The viewer page in a real browser: each page given is loaded from disk by headless
// Chromium (software WebGL, real time), the pages in turn, --repeat times; a row per page:
// its size, the status it set, and Chromium's wall time from start to the DOM dump after
// the page's load event (the viewer draws before that), fastest and median. The first row
// is about:blank: the browser's own start, to subtract. Pages of two builds side by side
// (for instance `medspheres view` of one robot by the main branch and by this one) give the
// ratio on one machine in one run.
//
// Usage: bench_view_page --page A.html --page B.html [--repeat 5]
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bench_timing.h"
#include "support/chromium.h"
#include "support/run_command.h"

namespace {

using namespace medspheres;

struct Row {
  std::string page, status;
  std::uintmax_t bytes = 0;
  std::vector<double> seconds;
};

// The body's data-status in the dumped DOM, or what went wrong.
std::string status_of(const test::CommandResult& r) {
  const std::size_t at = r.out.find("data-status=\"");
  if (at == std::string::npos) return "(no status; exit " + std::to_string(r.exit_code) + ")";
  const std::size_t from = at + 13;
  return r.out.substr(from, std::min<std::size_t>(r.out.find('"', from) - from, 40));
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> pages;
  int repeat = 5;
  bench::Args args("bench_view_page", "Viewer pages loaded by headless Chromium");
  args.add("--page", pages, "An HTML page `medspheres view` wrote (repeat the flag)")->required();
  args.add("--repeat", repeat, "Loads of each page");
  args.parse(argc, argv);
  const std::string chromium = test::find_chromium();
  if (chromium.empty()) {
    std::printf("no chromium on PATH\n");
    return 1;
  }
  std::vector<Row> rows = {{"about:blank", "", 0, {}}};
  for (const std::string& p : pages) rows.push_back({p, "", std::filesystem::file_size(p), {}});
  for (int k = 0; k < repeat; ++k)
    for (Row& row : rows) {
      const std::string url =
          row.bytes ? "file://" + std::filesystem::absolute(row.page).string() : row.page;
      const auto t0 = bench::Clock::now();
      const test::CommandResult r = test::run_command(test::chromium_command(
          chromium, "--window-size=1024,768 --dump-dom " + test::shell_quote(url), 0));
      row.seconds.push_back(bench::seconds_since(t0));
      row.status = row.bytes ? status_of(r) : "-";
    }
  std::printf("%-40s %12s %8s %8s  %s\n", "page", "bytes", "min s", "median s", "status");
  for (Row& row : rows) {
    std::sort(row.seconds.begin(), row.seconds.end());
    std::printf("%-40s %12ju %8.2f %8.2f  %s\n", row.page.c_str(), row.bytes, row.seconds.front(),
                row.seconds[row.seconds.size() / 2], row.status.c_str());
  }
  return 0;
}
