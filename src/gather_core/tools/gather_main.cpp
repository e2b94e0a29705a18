// gather: the command-line front end of gather_core.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "cli.hpp"
#include "commands.hpp"
#include "gather_core/error.hpp"

namespace {

struct Subcommand {
  const char* name;
  int (*run)(int, char**);
  const char* summary;
};

const Subcommand kSubcommands[] = {
    {"info", gather::cmd::info, "info SCENARIO          map size, free and reachable area, warnings"},
    {"limits", gather::cmd::limits,
     "limits                 every input's numeric range (scenario, map, plan.yaml, flags; docs/input_limits.md)"},
    {"fmm", gather::cmd::fmm,
     "fmm --map FILE --source ROW,COL [--sources-file F] [--order 1|2] [--out T.npy] [--labels L.npy] "
     "[--repeat K]  Fast Marching arrival times (image rows, 0 = top)"},
    {"partition", gather::cmd::partition,
     "partition SCENARIO --method bap|pap|rap --workers N [--seed K] [--gt GT.png] --out DIR | --compare --workers N "
     "--out DIR | --report [--workers N] [--repeat K] SCENARIO...  working areas, figures, metrics"},
    {"radio", gather::cmd::radio,
     "radio SCENARIO [--at X,Y] [--repeat K] [--out coverage.png]  radio coverage of the OC, median time"},
    {"plan", gather::cmd::plan,
     "plan SCENARIO --out DIR [--config METHOD:NC] [--seed K] [--threads T] [--association on|off]  deployment plan: "
     "utility sweep over "
     "(method, N_c), plan.yaml, report.csv, Fig. 2 and Fig. 3 (estimated)"},
    {"sim", gather::cmd::sim,
     "sim PLAN_DIR --out DIR [--cycles C] [--seeds K] [--seed S] [--all-configs] [--threads T] [--video F.mp4|.avi]  "
     "mission simulator: goals.csv, cycles.csv, summary.csv (simulated vs estimated refresh and goals), Fig. 3 bands "
     "(--all-configs), Fig. 4, video"},
#ifdef GATHER_WITH_RUN
    {"run", gather::cmd::run,
     "run PLAN_DIR --out DIR [--cycles C] [--seeds K] [--seed S] [--tick DT] [--loss P] [--loss-seed N]  the agent "
     "runtime, every role in one process (range gate, lockstep clock), or with --lcm (--key-file F | --insecure) one "
     "gather_agent process per agent: goals.csv, cycles.csv, summary.csv, agents.csv"},
    {"keygen", gather::cmd::keygen,
     "keygen FILE [--key-id N]  a new fleet master key (mode 0600) for signed fleet traffic: gather run --lcm "
     "--key-file, the OC's key_file; keygen FILE --agent K --plan PLAN_DIR --master MASTER  agent K's own keys, "
     "its links' only (gather_agent --key-file on that robot; docs/security.md)"},
#else
    {"run", nullptr, "run PLAN_DIR --out DIR ...  (needs the gather_agent package: build with it)"},
    {"keygen", nullptr, "keygen FILE  (needs the gather_agent package: build with it)"},
#endif
};

void usage(FILE* out) {
  std::fprintf(out, "usage: gather <command> [options]\n\ncommands:\n");
  for (const auto& s : kSubcommands) std::fprintf(out, "  %s\n", s.summary);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
    usage(argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  for (const auto& s : kSubcommands) {
    if (std::strcmp(argv[1], s.name) != 0) continue;
    if (!s.run) {
      std::fprintf(stderr, "gather %s: not built in this gather (build gather_agent beside gather_core)\n", s.name);
      return 2;
    }
    try {
      return s.run(argc, argv);
    } catch (const gather::cli::UsageError& e) {
      std::fprintf(stderr, "gather %s: %s (see gather --help)\n", s.name, e.what());
      return 2;
    } catch (const gather::RuntimeError& e) {
      std::fprintf(stderr, "gather %s: %s\n", s.name, e.what());
      return 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "gather %s: %s\n", s.name, e.what());
      return 2;
    }
  }
  std::fprintf(stderr, "gather: unknown command '%s' (see gather --help)\n", argv[1]);
  return 2;
}
