#pragma once
// One function per `gather` subcommand; each returns the process exit status.
namespace gather {
namespace cmd {

int info(int argc, char** argv);       // gather info SCENARIO
int limits(int argc, char** argv);     // gather limits
int fmm(int argc, char** argv);        // gather fmm --map FILE --source ROW,COL ... (tools/cmd_fmm.cpp)
int partition(int argc, char** argv);  // gather partition SCENARIO --method M --workers N ... (tools/cmd_partition.cpp)
int radio(int argc, char** argv);      // gather radio SCENARIO ... (tools/cmd_radio.cpp)
int plan(int argc, char** argv);       // gather plan SCENARIO --out DIR ... (tools/cmd_plan.cpp)
int sim(int argc, char** argv);        // gather sim PLAN_DIR --out DIR ... (tools/cmd_sim.cpp)
int run(int argc, char** argv);        // gather run PLAN_DIR --out DIR ... (gather_agent/tools/cmd_run.cpp)
int keygen(int argc, char** argv);     // gather keygen FILE (gather_agent/tools/cmd_run.cpp)

}  // namespace cmd
}  // namespace gather
