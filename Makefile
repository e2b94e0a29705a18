# gather: build, test and run. `make run` and `make test` work on a fresh
# Debian 12 machine: they install the missing packages first.
SHELL := /bin/bash
.ONESHELL:
.SHELLFLAGS := -eo pipefail -c

JOBS ?= 2
PYTHON := /usr/bin/python3
WS := catkin_ws
PLAIN := build/plain
SCENARIO ?= maps/campus_busy.scenario.yaml
CYCLES ?= 0
RESULTS ?= results/mission
SETUP := source $(WS)/devel/setup.bash

.PHONY: all deps pylcm build run readme-figures test format format-check tidy bench-fmm-ab test-ros plain-build test-plain plain-unit-bg test-plain-rest test-cli test-e2e bench-fmm bench-runtime bench-faults bench-robots bench-signing identity-check bench-planner bench-planner-scenarios partition-report scenario-report regime-report runtime-report clean help

all: build

help:
	@echo "make run     install deps, build, run the default mission headless, print a summary (results/)"
	@echo "make test    install deps, build, run every test (unit, plain CMake, ROS end-to-end)"
	@echo "make build   build the catkin workspace (Release)"

deps:
	@tools/install-deps

# The lcm package (PyPI) and the gather_lcm types for Python (lcm-gen
# --python), for the example robot driver and its test (docs/robots.md).
PYLCM := build/pylcm
pylcm: deps
	@test -f $(PYLCM)/lcm/__init__.py || $(PYTHON) -m pip install --quiet --disable-pip-version-check --target $(PYLCM) lcm
	lcm-gen -p --ppath $(PYLCM) src/gather_agent/lcm/*.lcm

build: deps
	catkin_make -C $(WS) -j$(JOBS) -DPYTHON_EXECUTABLE=$(PYTHON) -DCMAKE_BUILD_TYPE=Release --no-color

# Runs the default mission (campus_busy: workers and collectors) headless
# inside a private network namespace (LCM multicast stays on a private
# loopback): plans the scenario, runs its cycles with one process per agent,
# records a bag, prints what happened (how many goals came through a
# collector too). SCENARIO=maps/office.scenario.yaml for another.
run: build
	rm -rf $(RESULTS)
	tools/netns-run bash -c '$(SETUP) && roslaunch --log gather_oc mission.launch \
	  scenario:=$(abspath $(SCENARIO)) cycles:=$(CYCLES) results_dir:=$(abspath $(RESULTS)) record:=true \
	  $(if $(VIEW),rviz:=true rate:=$(or $(RATE),10) close_on_end:=true)'
	$(PYTHON) tools/mission_summary.py $(RESULTS)

# The README's first-screen pictures of the default scenario (Fig. 3: E
# beside R; RViz on its mission mid-run) -> docs/readme_fig3.png and
# docs/readme_mission.png (~3 min; RViz under Xvfb in a private namespace).
readme-figures: build
	tools/netns-run xvfb-run -a -s "-screen 0 1400x900x24" bash -c \
	  '$(SETUP) && $(PYTHON) tools/readme_figures.py --scenario $(abspath $(SCENARIO))'

# The CPU-bound checks that need no ROS (clang-tidy, the sanitized build of
# test-plain, then its unit tests but those that time the wall clock) run at
# nice 19 beside the ROS, CLI and end-to-end tests, which wait mostly on the
# wall clock (an e2e test uses about half of the 2 cores); then the unit
# tests that time the wall clock ($(WALL_CLOCK_TESTS): an agent process's
# exit, its clock's round trip) and the fuzz smoke (a timeout per case) run
# alone. The background's output is in build/test-background.log.
BG_LOG := build/test-background.log
test: build
	@mkdir -p build
	echo "make test: tidy and plain-build (the sanitized build) at nice 19 beside the other tests: $(BG_LOG)"
	# setsid -w: should setsid have to fork, it still waits for its child (so
	# `wait` gets the real status).
	setsid -w nice -n 19 $(MAKE) --no-print-directory -o deps tidy plain-unit-bg > $(BG_LOG) 2>&1 &
	bg=$$!
	trap 'kill -- -$$bg 2> /dev/null || true' EXIT
	t0=$$(date +%s)
	done_at() { echo "make test: $$1 done at $$(date +%T), $$(( $$(date +%s) - t0 )) s after the build"; }
	# -o build -o deps: built and installed above, not again for each phase.
	for t in format-check test-ros test-cli test-e2e; do $(MAKE) --no-print-directory -o build -o deps $$t; done_at $$t; done
	if ! wait $$bg; then
	  tail -n 150 $(BG_LOG) >&2
	  echo "make test: tidy, the sanitized build or its unit tests failed ($(BG_LOG))" >&2
	  exit 1
	fi
	trap - EXIT
	grep -E "tests passed|plain-build:" $(BG_LOG)
	done_at "tidy, plain-build and its unit tests (in the background)"
	$(MAKE) --no-print-directory -o deps -o plain-build test-plain-rest
	done_at "test-plain (the wall-clock unit tests and the fuzz smoke)"
	echo "make test: all tests passed"

# The committed .clang-format on every C++ file of the repository: `make
# format` applies it, `make format-check` (part of make test) fails on a file
# it would change.
CXX_SOURCES = git ls-files '*.cpp' '*.hpp'
format: deps
	$(CXX_SOURCES) | xargs clang-format-14 -i --style=file
format-check: deps
	@command -v clang-format-14 > /dev/null || { echo "format-check: clang-format-14 not found (make deps installs it)" >&2; exit 1; }
	@bad=$$($(CXX_SOURCES) | xargs clang-format-14 --style=file --dry-run 2>&1 | { grep -oE '^[^:]+:[0-9]+:[0-9]+: (warning|error)' || true; } | cut -d: -f1 | sort -u); \
	  if [ -n "$$bad" ]; then echo "format-check: not formatted (make format fixes it):" >&2; echo "$$bad" >&2; exit 1; fi
	@echo "format-check: every C++ file follows .clang-format"

# clang-tidy (.clang-tidy) over gather_core; any finding fails.
tidy: deps
	tools/run-tidy $(JOBS)

# GoogleTest suites of gather_oc through catkin (those of gather_core and
# gather_agent run in test-plain, under the sanitizers: no need to build and
# run them twice).
test-ros: build
	rm -rf $(WS)/build/test_results
	tools/netns-run bash -c '$(SETUP) && catkin_make -C $(WS) -j$(JOBS) run_tests_gather_oc run_tests_gather_world --no-color > $(WS)/build/run_tests.log 2>&1' \
	  || { tail -n 60 $(WS)/build/run_tests.log; echo "test-ros: building or running the tests failed" >&2; exit 1; }
	catkin_test_results --verbose $(WS)/build/test_results | tee $(WS)/build/test_results.txt | tail -n 40
	@grep -qE "^Summary: [1-9][0-9]* tests, 0 errors, 0 failures" $(WS)/build/test_results.txt \
	  || { echo "test-ros: no test results found (catkin_test_results)" >&2; exit 1; }

# gather_core and gather_agent as plain CMake projects, no ROS, own build
# dir, built with AddressSanitizer + UndefinedBehaviorSanitizer (+ float-cast-
# overflow; any report aborts): the unit tests (LCM payload fuzzing among
# them), then the seeded mutation fuzz smoke over scenarios, maps, plan
# directories and flags (tests/fuzz/fuzz_smoke.py; docs/input_limits.md).
FUZZ_CASES ?= 300
plain-build: deps
	@if grep -rnE '#include [<"](ros|nav_msgs|visualization_msgs|std_msgs)/' src/gather_core src/gather_agent tests/core tests/agent; then \
	  echo "gather_core/gather_agent must not include ROS headers" >&2; exit 1; fi
	cmake -S src/gather_agent -B $(PLAIN) -DCMAKE_BUILD_TYPE=Release -DGATHER_SANITIZE=ON > /dev/null
	cmake --build $(PLAIN) -j$(JOBS)
	@test -x $(PLAIN)/gather_agent && if ldd $(PLAIN)/gather_agent | grep -q libopencv; then echo "gather_agent must not link OpenCV (figures live in gather_figures)" >&2; exit 1; fi
	@if ldd $(PLAIN)/gather_core/gather | grep -qE 'libopencv_(videoio|imgcodecs)'; then echo "gather must not link OpenCV's videoio or imgcodecs (the video encoder is the module gather_video; PNGs go through libpng)" >&2; exit 1; fi
	@test -f $(PLAIN)/gather_core/libgather_video.so || { echo "plain-build: the video module libgather_video.so was not built" >&2; exit 1; }
	@echo "plain-build: gather_core and gather_agent built with the sanitizers ($(PLAIN))"
PLAIN_CTEST = ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir $(PLAIN) --output-on-failure -j$(JOBS) --timeout 600
FUZZ_SMOKE = $(PYTHON) tests/fuzz/fuzz_smoke.py --gather $(PLAIN)/gather_core/gather --agent $(PLAIN)/gather_agent \
  --cases $(FUZZ_CASES) --seed 1 --jobs $(JOBS) --keep results/fuzz
WALL_CLOCK_TESTS := ^(AgentProcess|FleetClock)[.]
test-plain: plain-build
	$(PLAIN_CTEST)
	$(FUZZ_SMOKE)
# make test's split of test-plain: the background part, then the rest.
plain-unit-bg: plain-build
	$(PLAIN_CTEST) -E '$(WALL_CLOCK_TESTS)'
test-plain-rest: plain-build
	$(PLAIN_CTEST) -R '$(WALL_CLOCK_TESTS)'
	$(FUZZ_SMOKE)

# Every bad input gives one line naming the file and exit status 2, from every
# binary: bad scenarios, and bad plan directories.
G := $(WS)/devel/lib/gather_core/gather
TEST_KEY := $(WS)/build/test_fleet.key
test-cli: build
	@for b in $(WS)/devel/lib/gather_oc/fleet_node $(WS)/devel/lib/gather_agent/gather_agent; do \
	  test -x $$b || { echo "$$b missing" >&2; exit 1; }; if ldd $$b | grep -q libopencv; then echo "$$b must not link OpenCV (figures live in gather_figures)" >&2; exit 1; fi; done
	@if ldd $(WS)/devel/lib/gather_agent/gather_agent | grep -qE 'libmrpt|libompl'; then echo "gather_agent must not link MRPT or OMPL (MRPT lives in gather_world)" >&2; exit 1; fi
	test -f $(TEST_KEY) || $(G) keygen $(TEST_KEY)
	tests/cli/bad_input.sh "$(G) info"
	tests/cli/bad_input.sh "$(WS)/devel/lib/gather_oc/oc_node"
	tests/cli/bad_input.sh "$(WS)/devel/lib/gather_oc/fleet_node"
	tests/cli/bad_plan.sh $(G) "$(G) run --out $(WS)/build/bad_plan_run"
	tests/cli/bad_plan.sh $(G) "$(WS)/devel/lib/gather_agent/gather_agent --id 0 --lcm-url memq:// --silence 5 --key-file $(TEST_KEY) --plan"
	tests/cli/bad_plan.sh $(G) "$(WS)/devel/lib/gather_oc/oc_node $(abspath maps/office.scenario.yaml)"
	tests/cli/world_pace.sh $(WS)/devel/lib/gather_world/gather_world_pace
	tests/cli/video.sh $(G)
	tests/cli/bad_flags.sh $(G)
	tests/cli/agent_silence.sh $(G) $(WS)/devel/lib/gather_agent/gather_agent
	tools/netns-run $(PYTHON) tests/cli/range_ends.py --gather $(G) --agent $(WS)/devel/lib/gather_agent/gather_agent \
	  --mission-bag $(WS)/devel/lib/gather_oc/mission_bag
	$(PYTHON) tests/cli/range_ends.py --gather $(G) --agent - --mission-bag - --largest-map

# The agent runtime over LCM against one process (gather run --lcm), and
# roslaunch gather_oc mission.launch / review.launch end to end with RViz on a
# virtual display (screenshots in results/e2e/), in a private network namespace;
# then two robots through robot.launch, robot_bridge and move_base's topics
# (world_move_base on gather_world), and a mission with the OC and every
# robot its own host (tools/hosts-run).
# robots_e2e and bridge_e2e run side by side (each in a namespace of its
# own, about one core between them; robots_e2e's output follows bridge_e2e's).
test-e2e: build pylcm
	tools/netns-run $(PYTHON) tests/e2e/runtime_e2e.py
	tools/netns-run xvfb-run -a -s "-screen 0 1400x900x24" bash -c '$(SETUP) && $(PYTHON) tests/e2e/mission_e2e.py'
	mkdir -p build
	setsid -w tools/netns-run bash -c '$(SETUP) && $(PYTHON) tests/e2e/robots_e2e.py --pylcm $(PYLCM) --launch' \
	  > build/robots_e2e.log 2>&1 &
	robots=$$!
	trap 'kill -- -$$robots 2> /dev/null || true; echo "test-e2e: robots_e2e stopped (its output: build/robots_e2e.log)" >&2' EXIT
	tools/netns-run bash -c '$(SETUP) && $(PYTHON) tests/e2e/bridge_e2e.py'
	status=0; wait $$robots || status=$$?
	trap - EXIT
	cat build/robots_e2e.log
	if [ $$status -ne 0 ]; then echo "test-e2e: robots_e2e failed (status $$status)" >&2; exit 1; fi
	tools/hosts-run 20 $(PYTHON) tests/e2e/hosts_e2e.py --pylcm $(PYLCM)

# FMM against scikit-fmm on the shared benchmark grids, one table (docs/fmm.md);
# plus the Google Benchmark micro-benchmarks of the solver.
bench-fmm: build
	bench/fmm_bench.sh $(WS)/devel/lib/gather_core/gather
	cmake -S src/gather_core -B build/bench -DCMAKE_BUILD_TYPE=Release -DGATHER_BUILD_BENCH=ON -DBUILD_TESTING=OFF > /dev/null
	cmake --build build/bench -j$(JOBS) --target gather_fmm_micro
	build/bench/gather_fmm_micro --benchmark_repetitions=3 --benchmark_report_aggregates_only=true

# The FMM of REF's tree against this tree's, both static plain builds, on the
# shared benchmark grids (bench/fmm_ab.sh; ~8 min with the two builds).
bench-fmm-ab: deps
	@test -n "$(REF)" || { echo "usage: make bench-fmm-ab REF=<commit>" >&2; exit 2; }
	tools/build-ref $(REF) build/ab_ref $(JOBS)
	cmake -S src/gather_agent -B build/ab_new -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF > /dev/null
	cmake --build build/ab_new -j$(JOBS) --target gather > /dev/null
	bench/fmm_ab.sh build/ab_ref/build/gather_core/gather build/ab_new/gather_core/gather

# The agent runtime on maps/office: in one process and one process per agent
# over LCM (x real time, messages/s, where a tick goes, agent memory); ~3 min.
bench-runtime: build
	tools/netns-run $(PYTHON) bench/runtime_bench.py

# The agents against the analytic simulator on maps/office and office_a, and
# over LCM against one process -> docs/runtime_equivalence.md (~4 min).
runtime-report: build
	tools/netns-run $(PYTHON) tools/runtime_report.py

# Faults on maps/office (pap:4 with busy collectors, bap:0; 10 cycles, 5
# seeds): 20% loss, one worker or collector killed (each repair), an agent
# carrying data crashed and restarted from its journal ->
# docs/faults_bench.md (~5 min; fails when a target is not met).
bench-faults: build
	$(PYTHON) tools/fault_bench.py

# The team on gather_world's MRPT robots beside ideal bases: office and
# office_a, pap:4 and the best plan, and the best plan of warehouse, campus and
# cave, 5 seeds x 10 cycles -> docs/robots_bench.md (delivered goals and both
# refresh metrics, robots / ideal; late waypoints, collector delays,
# navigation failures, contacts; x real time). About 25 minutes.
SEEDS ?= 5
bench-robots: build
	$(PYTHON) tools/robots_bench.py --seeds $(SEEDS)

# The cost of signed fleet traffic: sign/verify per message, and the fleet
# over LCM signed vs unsigned on maps/office (docs/security.md); ~4 min.
bench-signing: build
	tools/netns-run bench/signing_bench.sh $(G)

# The planner at scale: gather plan's sweep for teams of 20, 50, 100 and 200
# on maps/office and maps/campus, beside a static build of PLANNER_REF (the
# commit before the planner's speed-ups) -> docs/planner_bench.md and .png.
# The reference runs at REF_TEAMS only (minutes a sweep at 100 robots, 11-18 at
# 200). About 20 min; TEAMS=20,50,100 shortens it.
PLANNER_REF ?= 0e97da5
TEAMS ?= 20,50,100,200
REF_TEAMS ?= 20,50,100
bench-planner: build
	tools/build-ref $(PLANNER_REF) build/planner_ref $(JOBS)
	$(PYTHON) tools/planner_bench.py --ref build/planner_ref/build/gather_core/gather --ref-name $(PLANNER_REF) \
	  --new $(G) --teams $(TEAMS) --ref-teams $(REF_TEAMS) --runs $(or $(RUNS),3)

# The shipped scenarios' sweeps beside the reference's (the same build of
# PLANNER_REF as bench-planner's: do not run both at once), and the simulated
# quality of the plan each chooses -> docs/planner_scenarios.md (~4 min, and
# about 1 min to build the reference the first time).
bench-planner-scenarios: build
	tools/build-ref $(PLANNER_REF) build/planner_ref $(JOBS)
	$(PYTHON) tools/planner_scenarios.py --ref build/planner_ref/build/gather_core/gather --ref-name $(PLANNER_REF) \
	  --new $(G) --runs $(or $(RUNS),3)

# A refactor changes no result: plan.yaml, report.csv (timings aside) and
# goals.csv of office and office_a (their best plans, and two plans with
# collectors at work) from REF's gather and from this tree's.
identity-check: build
	@test -n "$(REF)" || { echo "usage: make identity-check REF=<commit>" >&2; exit 2; }
	tools/build-ref $(REF) build/identity_ref $(JOBS)
	$(PYTHON) tools/identity_check.py --before build/identity_ref/build/gather_core/gather --after $(G)

# Partition metrics of BAP/PAP/RAP on every map -> docs/partitions.md.
partition-report: build
	tools/partition_report.sh $(WS)/devel/lib/gather_core

# Plan (median sweep time of 3) and simulate every configuration (5 seeds) on
# every scenario -> docs/scenarios.md, and on the office variants ->
# docs/variants.md; figures in results/scenarios/ (~8 min).
scenario-report: build
	$(PYTHON) tools/scenario_report.py
	$(PYTHON) tools/scenario_report.py --out docs/variants.md maps/variants/*.scenario.yaml

# Where collectors pay off: on office, campus and office_a, every
# (coverage, goals per request, request period) of a 3x3x2 grid planned and
# simulated (27 configurations, 2 seeds x 3 cycles each) -> docs/regimes.md
# and one figure per map in results/regimes/ (about 40 min: docs/regimes.md).
regime-report: build
	$(PYTHON) tools/regime_report.py

clean:
	rm -rf $(WS)/build $(WS)/devel $(WS)/install build results src/CMakeLists.txt
