# Virtual respirator fit: top-level entry points.
#   make case=medium_onesize   run the pipeline for one case (builds what is out of date)
#   make test                  build everything and run all tests
#   make cases-all             all 30 cases;  make help  for more
# Both install the missing Debian packages first (scripts/install-deps.sh).

include scripts/user_variables.mk
JOBS ?= 2
export BUILD

.PHONY: help deps build stages test test-fast bench case cases-all clean
.DEFAULT_GOAL := $(if $(case),case,help)

help:
	@echo "make case=<headform>_<respirator>   e.g. make case=medium_onesize (cases in data/cases/)"
	@echo "   HEADFORM_SCAN=path RESPIRATOR_SCAN=path   swap in your own scans"
	@echo "   HEADFORM_UNIT=u RESPIRATOR_UNIT=u         their length unit: auto (default), mm, cm, m, in"
	@echo "   LANDMARKS=file.json                       your own head landmarks (README.md, Stages)"
	@echo "   STRAP_LENGTH_MM=n STRAP_WIDTH_MM=n STRAP_THICKNESS_MM=n GAP_MM=n BRIDGE_OFFSET_MM=n MAX_RIM_OFF_MM=n"
	@echo "      the case's strap and placement settings [mm], to straps and assemble alike (their --help;"
	@echo "      unset: their defaults); also in the case file, data/cases/<case>.mk"
	@echo "   BUILD=dir (default build)  JOBS=n (default 2: compile jobs and tests at once)"
	@echo "make stages      build only the stage programs"
	@echo "make test        build and run all tests (CTest)"
	@echo "make test-fast   tests not labelled slow"
	@echo "make bench       build and run the benchmarks"
	@echo "make cases-all   run all 30 cases"
	@echo "make deps        install the missing Debian packages (scripts/install-deps.sh)"
	@echo "make build       configure and build everything (programs, tests, benchmarks)"
	@echo "make clean       remove the build folder"

deps:
	@scripts/install-deps.sh

# Ninja when present (install-deps installs it): it compiles a target's files while the libraries
# the target links are still being archived, where make goes target by target. Only for a new build
# directory: an existing one keeps the generator it was made with.
$(BUILD)/CMakeCache.txt: CMakeLists.txt
	@scripts/install-deps.sh
	cmake -S . -B $(BUILD) $$(test -f $(BUILD)/CMakeCache.txt || ! command -v ninja >/dev/null || echo -G Ninja) \
	  -DCMAKE_BUILD_TYPE=Release

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

# ctest runs JOBS tests at once, one per core, so each test gets one OpenMP thread (unless
# OMP_NUM_THREADS is set): two-thread tests beside another test spun their threads on a busy core
# (paired runs of the 172 tests there were then: contact_hertz 125 s with two threads, 78 s with one; the whole
# ctest 572 s -> 478 s wall). Tests that compare thread counts set them themselves.
TEST_ENV := OMP_NUM_THREADS=$${OMP_NUM_THREADS:-1}

test: build
	cd $(BUILD) && $(TEST_ENV) ctest --output-on-failure -j $(JOBS) --timeout 1500

test-fast: build
	cd $(BUILD) && $(TEST_ENV) ctest --output-on-failure -j $(JOBS) -LE slow

# Each benchmark with the input its figures in the READMEs were measured on; bench_model needs
# the medium_onesize case's surface meshes, so that case runs first.
bench: build
	$(BUILD)/bin/bench_elements
	$(BUILD)/bin/bench_contact
	$(BUILD)/bin/bench_scan2cad --mesh ../shared/data/headforms/NIOSH_medium_20k.stl --points 1000000
	$(MAKE) --no-print-directory -f Makefile.cases case=medium_onesize
	$(BUILD)/bin/bench_model --case $(BUILD)/cases/medium_onesize --materials data/materials.json

# A case needs only the stage programs, not the tests and benchmarks.
STAGE_PROGRAMS := generate_scan reconstruct repair align landmarks segment fit surface_mesh layers straps assemble solve

stages: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS) --target $(STAGE_PROGRAMS)

case: stages
	$(MAKE) --no-print-directory -f Makefile.cases case=$(case)

# Every case is tried even when one fails; the summary names the failures and the exit status
# says whether all 30 reached their outputs.
cases-all: stages
	@failed=""; for c in $(basename $(notdir $(wildcard data/cases/*.mk))); do \
	  $(MAKE) --no-print-directory -f Makefile.cases case=$$c || failed="$$failed $$c"; done; \
	if [ -n "$$failed" ]; then echo "cases-all: FAILED:$$failed"; exit 1; fi; \
	echo "cases-all: all $(words $(wildcard data/cases/*.mk)) cases done"

clean:
	rm -rf $(BUILD)
