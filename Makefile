# Build, test, demo and benchmark entry points of the body scan workspace.
#
# The repository root is the catkin source space (CMakeLists.txt -> catkin's toplevel.cmake);
# everything is built with plain cmake into build/ (devel space: build/devel).
#
# Gotcha: `python3` on PATH may be a pyenv shim without catkin_pkg. catkin, rostest and our
# scripts need Debian's /usr/bin/python3, so every recipe runs with /usr/bin first in PATH and
# cmake gets -DPYTHON_EXECUTABLE=/usr/bin/python3.
#
#   make deps    install missing Debian packages (no-op when all are installed)
#   make build   configure + build all packages into build/ (devel space build/devel, install
#                space build/install)
#   make test    build + run every gtest/rostest; last line: "N passed, N failed, N skipped"
#   make demo    build + scripts/demo.sh
#   make bench   build + run every build/devel/lib/*/bench_* (JSON into build/bench/);
#                BENCH_ARGS="..." is passed to each (e.g. --benchmark_filter=plane/hot)
#   make soak    build + scripts/soak.py: SOAK_SCANS (default 300) consecutive scans of the
#                headless simulated scanner; latency p50/p99, every node's RSS, missing scans
#                (report build/soak/soak.yaml); not part of `make test` (about 25 min)
#   make results build + scripts/results.py: regenerates docs/RESULTS.md, every table of figures
#                from the command that measures it (about 30 min on 2 cores; RESULTS_QUICK=1:
#                smaller sizes, about 15 min); fits cached in build/results/fit_cache
#   make format  clang-format -i every C++ file of the packages
#   make fuzz    build every libFuzzer target (fuzz_* of the packages) with clang, ASan and
#                UBSan in build/sanitize and run each FUZZ_SECONDS (default 60) from its checked-
#                in corpus; findings in build/fuzz/<target>/
#   make sanitize  the unit tests and rostests built with clang, ASan and UBSan in build/sanitize
#                (JUnit into build/sanitize/test_results), then the multi-threaded parts' tests
#                with TSan in build/tsan; reports: build/sanitize/reports/
#   make clean   remove build/

SHELL := /bin/bash
export PATH := /usr/bin:$(PATH)
MAKEFLAGS += --no-print-directory

PY        := /usr/bin/python3
BUILD_DIR := $(CURDIR)/build
JOBS      ?= 2
BENCH_ARGS ?=
CMAKE_BUILD_TYPE ?= Release

# Debian packages the whole suite needs to build, test, run the demo and the benchmarks. They are
# the Debian names of the packages' package.xml keys (scripts/check_deps.py, run by `make test`,
# checks that both lists agree), plus a few that no package.xml covers:
#   ros-base-dev, ros-core, rosbash: the ROS base set a ROS user has, roscore/rostopic/
#       rosservice/rosrun (scripts/demo.sh, the README's commands)
#   opencv-doc: OpenCV's sample chessboard images (a calibration test)
DEB_PACKAGES := \
	catkin pkg-config ros-base-dev ros-core rosbash ros-message-generation ros-message-runtime \
	libroscpp-dev libroslib-dev python3-rospy python3-roslaunch libnodeletlib-dev \
	libnodeletlib-tools pluginlib-dev librostest-dev python3-rostest rviz \
	libstd-msgs-dev libstd-srvs-dev libgeometry-msgs-dev libsensor-msgs-dev python3-sensor-msgs \
	libvisualization-msgs-dev python3-visualization-msgs libdiagnostic-msgs-dev \
	python3-diagnostic-msgs libtf2-ros-dev libcamera-calibration-parsers-dev librosbag-dev \
	python3-rosbag libdiagnostic-updater-dev libdynamic-reconfigure-config-init-mutex-dev \
	python3-dynamic-reconfigure \
	libopencv-dev libopencv-contrib-dev libeigen3-dev libyaml-cpp-dev libceres-dev libpcl-dev \
	libsqlite3-dev libcli11-dev libusb-1.0-0-dev libuvc-dev libx11-dev libembree-dev \
	libgtest-dev libbenchmark-dev libtinyxml2-dev xvfb opencv-doc

# Only `make format` needs these.
FORMAT_PACKAGES := clang-format
# Only `make fuzz` and `make sanitize` need these (clang, libFuzzer and the sanitizer runtimes).
SANITIZER_PACKAGES := clang-14 libclang-rt-14-dev

# Catkin packages = top-level directories with a package.xml.
PACKAGES := $(patsubst %/package.xml,%,$(wildcard */package.xml))

# $(call install_missing,PACKAGES): apt-get install those of PACKAGES that dpkg does not
# report as installed (through sudo unless root, as in CI); prints nothing and calls nothing
# when all are there.
define install_missing
	@missing=""; \
	for p in $(1); do \
	  dpkg-query -W -f='$${db:Status-Status}\n' "$$p" 2>/dev/null | grep -qx installed \
	    || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  sudo=""; [ "$$(id -u)" = 0 ] || sudo=sudo; \
	  echo "Installing missing Debian packages:$$missing"; \
	  apt="$$sudo env DEBIAN_FRONTEND=noninteractive apt-get"; \
	  $$apt update && $$apt install -y --no-install-recommends $$missing; \
	fi
endef

.PHONY: deps build test demo bench results format clean fuzz soak sanitize sanitize-build tsan

# deps: install the Debian packages in DEB_PACKAGES that are missing (idempotent).
deps:
	$(call install_missing,$(DEB_PACKAGES))

# build: configure the catkin workspace with cmake into build/ and build everything. The
# install space is build/install (`cmake --install build`; the install-space test does it).
# build/CATKIN_IGNORE keeps catkin from looking for packages inside build/.
# The devel space's Python folder is made before configuring: catkin caches the test
# environment (catkin_generated/setup_cached.sh) at configure time and leaves out folders that
# do not exist yet, so a fresh clone's Python tests and nodes would not find our messages.
build: deps
	@mkdir -p $(BUILD_DIR)/devel/lib/python3/dist-packages && touch $(BUILD_DIR)/CATKIN_IGNORE
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(CMAKE_BUILD_TYPE) \
	  -DPYTHON_EXECUTABLE=$(PY) -DCATKIN_DEVEL_PREFIX=$(BUILD_DIR)/devel \
	  -DCMAKE_INSTALL_PREFIX=$(BUILD_DIR)/install -DCATKIN_ENABLE_TESTING=ON
	cmake --build $(BUILD_DIR) -j$(JOBS)

# test: build the test binaries, run all gtests and rostests through catkin's run_tests
# (JUnit XML into build/test_results), then summarise with scripts/test_summary.py, whose
# "N passed, N failed, N skipped" line is the last line of the target's standard output.
# ROS_HOME/ROS_LOG_DIR live in build/ros_home and the master port is a fresh free one.
# Even when the build fails, the summary ("0 passed, 0 failed, 0 skipped") is printed and written.
test: deps
	@rm -rf $(BUILD_DIR)/test_results $(BUILD_DIR)/test_summary.txt
	@if ! { $(MAKE) build && $(MAKE) -C $(BUILD_DIR) -j$(JOBS) tests; }; then \
	  echo "== BUILD FAILED: no tests were run"; \
	  $(PY) scripts/test_summary.py $(BUILD_DIR)/test_results \
	    --write $(BUILD_DIR)/test_summary.txt; \
	  exit 1; \
	fi
	@port=$$($(PY) -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'); \
	export ROS_MASTER_URI=http://localhost:$$port; \
	export ROS_HOME=$(BUILD_DIR)/ros_home ROS_LOG_DIR=$(BUILD_DIR)/ros_home/log; \
	mkdir -p "$$ROS_LOG_DIR"; \
	echo "== running tests (ROS_MASTER_URI=$$ROS_MASTER_URI, ROS_HOME=$$ROS_HOME)"; \
	rt=0; $(MAKE) -C $(BUILD_DIR) run_tests || rt=$$?; \
	if [ $$rt -ne 0 ]; then echo "== WARNING: 'make run_tests' exited with status $$rt"; fi; \
	echo "== test summary (from build/test_results/**/*.xml)"; \
	st=0; $(PY) scripts/test_summary.py $(BUILD_DIR)/test_results \
	  --write $(BUILD_DIR)/test_summary.txt || st=$$?; \
	[ $$st -eq 0 ] && [ $$rt -eq 0 ]

# demo: build, then run the end-to-end demo script.
demo: build
	bash scripts/demo.sh

# bench: build, then run every Google Benchmark executable build/devel/lib/<pkg>/bench_*
# (with $(BENCH_ARGS)), printing its console table and saving JSON to build/bench/<name>.json,
# then the medians and the ratios of each peer to our implementation (scripts/bench_report.py
# -> build/bench/report.txt).
bench: build
	@mkdir -p $(BUILD_DIR)/bench; \
	found=0; \
	for exe in $(BUILD_DIR)/devel/lib/*/bench_*; do \
	  [ -f "$$exe" ] && [ -x "$$exe" ] || continue; \
	  found=1; name=$$(basename "$$exe"); \
	  echo "== $$name"; \
	  "$$exe" --benchmark_out=$(BUILD_DIR)/bench/$$name.json --benchmark_out_format=json \
	    $(BENCH_ARGS) || exit 1; \
	done; \
	if [ $$found -eq 0 ]; then echo "no bench_* executables under build/devel/lib/*/"; exit 1; fi; \
	echo "== ratios against ours (also in build/bench/report.txt)"; \
	$(PY) scripts/bench_report.py $(BUILD_DIR)/bench/bench_*.json

# results: build, plus the unit tests whose `[ figure ]` lines it reports, then
# scripts/results.py, which runs the evaluation tools, tests and benchmarks and writes
# docs/RESULTS.md (and the pictures the tools draw: docs/calibration/, docs/images/).
RESULTS_TESTS := test_stripe_decoder test_triangulation test_camera_calibration_images \
	test_real_captures test_pattern_contrast test_rig
results: build
	cmake --build $(BUILD_DIR) -j$(JOBS) --target $(RESULTS_TESTS)
	$(PY) scripts/results.py

# soak: build, then the long run of the whole scanner (scripts/soak.py). Fails on a missing scan,
# a node's RSS growing > 5 % over the run after the warm-up scans at the rate from the run's
# second quarter to its last (the floor of the samples taken every 5 scans: a single reading
# swings with what the node holds at that moment, and a high-water mark levels off early where a
# leak goes on), or latency p99 > 2 x p50.
SOAK_SCANS ?= 300
soak: build
	source $(BUILD_DIR)/devel/setup.bash && $(PY) scripts/soak.py --scans $(SOAK_SCANS)

# format: clang-format -i (style: .clang-format) every .cpp/.h/.hpp of the catkin packages.
format:
	$(call install_missing,$(FORMAT_PACKAGES))
	@files=$$(find $(PACKAGES) -type f \( -name '*.cpp' -o -name '*.h' -o -name '*.hpp' \)); \
	if [ -n "$$files" ]; then clang-format -i --style=file $$files; fi

# Sanitizer builds: clang with AddressSanitizer + UndefinedBehaviorSanitizer (any UB aborts),
# plus libFuzzer's coverage instrumentation, so the fuzz targets and the sanitized tests share
# one build (build/sanitize, configured with BODY_SCAN_FUZZ=ON; benchmarks off). The ASan
# runtime is shared (-shared-libasan) and preloaded into every process of a run, because the
# nodelet manager and python (rostest) are not instrumented but load our libraries.
SAN_DIR   := $(BUILD_DIR)/sanitize
TSAN_DIR  := $(BUILD_DIR)/tsan
CLANG_CC  ?= clang-14
CLANG_CXX ?= clang++-14
SAN_FLAGS := -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined \
	-fno-sanitize-recover=undefined -fsanitize=fuzzer-no-link -shared-libasan
ASAN_RT    = $(shell $(CLANG_CXX) -print-file-name=libclang_rt.asan-x86_64.so)
# detect_leaks=0: ROS's and python's own allocations at exit are not ours to chase.
# The tests' time limits and waits (rostest time-limit, the launch tests' timeouts) are
# stretched by BODY_SCAN_TEST_TIME_SCALE: sanitized nodes run several times slower.
SAN_TIME_SCALE ?= 8
SAN_ENV    = BODY_SCAN_TEST_TIME_SCALE=$(SAN_TIME_SCALE) LD_PRELOAD=$(ASAN_RT) \
	ASAN_OPTIONS=detect_leaks=0:verify_asan_link_order=0:abort_on_error=1:log_path=$(SAN_DIR)/reports/asan \
	UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:log_path=$(SAN_DIR)/reports/ubsan
# ccache, when installed, keeps a rebuild of a sanitizer tree short (a first build is long).
CCACHE_LAUNCHER := $(if $(shell command -v ccache),-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# configure (+ build $(1), a list of targets) of a sanitizer build dir $(2) with flags $(3)
define san_build
	@mkdir -p $(2)/devel/lib/python3/dist-packages && touch $(2)/CATKIN_IGNORE
	cmake -S . -B $(2) -DCMAKE_BUILD_TYPE=None -DCMAKE_C_COMPILER=$(CLANG_CC) \
	  -DCMAKE_CXX_COMPILER=$(CLANG_CXX) -DCMAKE_C_FLAGS="$(3)" -DCMAKE_CXX_FLAGS="$(3)" \
	  -DCMAKE_EXE_LINKER_FLAGS="$(3)" -DCMAKE_SHARED_LINKER_FLAGS="$(3)" \
	  -DPYTHON_EXECUTABLE=$(PY) -DCATKIN_DEVEL_PREFIX=$(2)/devel -DCMAKE_INSTALL_PREFIX=$(2)/install \
	  -DCATKIN_ENABLE_TESTING=ON $(CCACHE_LAUNCHER) \
	  -DCMAKE_DISABLE_FIND_PACKAGE_benchmark=ON $(4) >$(2)/configure.log
	cmake --build $(2) -j$(JOBS) $(if $(1),--target $(1))
endef

# fuzz: every fuzz_* target, each FUZZ_SECONDS from its corpus (<pkg>/fuzz/corpus/<name>, copied
# to build/fuzz/<name>/corpus, where the run's new inputs go), at most FUZZ_MAX_LEN bytes.
# Prints each target's executions and crashes; exits non-zero on any crash.
FUZZ_SECONDS ?= 60
FUZZ_MAX_LEN ?= 200000
fuzz:
	$(call install_missing,$(SANITIZER_PACKAGES))
	$(call san_build,fuzz_targets,$(SAN_DIR),$(SAN_FLAGS),-DBODY_SCAN_FUZZ=ON)
	@mkdir -p $(SAN_DIR)/reports; status=0; \
	for exe in $(SAN_DIR)/devel/lib/*/fuzz_*; do \
	  name=$$(basename $$exe); name=$${name#fuzz_}; pkg=$$(basename $$(dirname $$exe)); \
	  out=$(BUILD_DIR)/fuzz/$$name; mkdir -p $$out/corpus; \
	  cp -n $$pkg/fuzz/corpus/$$name/* $$out/corpus/ 2>/dev/null || true; \
	  (cd $$out && env LD_PRELOAD=$(ASAN_RT) UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	    ASAN_OPTIONS=detect_leaks=0:verify_asan_link_order=0:alloc_dealloc_mismatch=0 \
	    $$exe -max_total_time=$(FUZZ_SECONDS) -max_len=$(FUZZ_MAX_LEN) -rss_limit_mb=2048 \
	    -timeout=20 -print_final_stats=1 corpus >$$out/log.txt 2>&1) || status=1; \
	  runs=$$(sed -n 's/^stat::number_of_executed_units: *//p' $$out/log.txt); \
	  crashes=$$(ls $$out | grep -c -E '^(crash|leak|timeout|oom)-' || true); \
	  printf '%-22s %10s executions  %s crashes\n' $$name "$${runs:-?}" $$crashes; \
	done; exit $$status

# sanitize: the whole suite's tests under ASan + UBSan (a rostest's nodes too), then TSan.
# SAN_TESTS="test_a test_b ..." builds those targets and runs its test_* gtests, and the rostests
# of SAN_ROSTESTS="pkg/name.test ..." (their test_<name> and nodes must be in SAN_TESTS):
# a full sanitizer build takes long. A report aborts its process (the test fails);
# reports: build/sanitize/reports/.
SAN_TESTS ?=
SAN_ROSTESTS ?=
sanitize:
	$(call install_missing,$(SANITIZER_PACKAGES))
	$(call san_build,$(if $(SAN_TESTS),$(SAN_TESTS),all tests),$(SAN_DIR),$(SAN_FLAGS),-DBODY_SCAN_FUZZ=ON)
	@rm -rf $(SAN_DIR)/test_results $(SAN_DIR)/reports; mkdir -p $(SAN_DIR)/reports
	@port=$$($(PY) -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'); \
	export ROS_MASTER_URI=http://localhost:$$port; \
	export ROS_HOME=$(SAN_DIR)/ros_home ROS_LOG_DIR=$(SAN_DIR)/ros_home/log; \
	mkdir -p "$$ROS_LOG_DIR"; \
	if [ -z "$(SAN_TESTS)" ]; then \
	  env $(SAN_ENV) $(MAKE) -C $(SAN_DIR) run_tests || true; \
	  $(PY) scripts/test_summary.py $(SAN_DIR)/test_results --write $(SAN_DIR)/test_summary.txt; \
	else \
	  source $(SAN_DIR)/devel/setup.bash; passed=0; failed=0; \
	  for t in $(SAN_TESTS); do \
	    exe=$$(find $(SAN_DIR)/devel/lib -name $$t -type f | head -1); \
	    case " $(SAN_ROSTESTS) " in *"/$${t#test_}.test "*) continue;; esac; \
	    case $$t in test_*) [ -n "$$exe" ] || continue;; *) continue;; esac; \
	    if env $(SAN_ENV) $$exe >$(SAN_DIR)/reports/$$t.out 2>&1; then passed=$$((passed+1)); \
	      echo "asan $$t: $$(grep -o '[0-9]* tests\? from .* ran' $(SAN_DIR)/reports/$$t.out | tail -1) ok"; \
	    else failed=$$((failed+1)); echo "asan $$t: FAILED (build/sanitize/reports/$$t.out)"; fi; \
	  done; \
	  for r in $(SAN_ROSTESTS); do \
	    if env $(SAN_ENV) rostest --text $${r%%/*} $${r#*/} >$(SAN_DIR)/reports/$$(basename $$r).out 2>&1; \
	    then passed=$$((passed+1)); echo "asan rostest $$r: ok"; \
	    else failed=$$((failed+1)); echo "asan rostest $$r: FAILED"; fi; \
	  done; echo "== $$passed passed, $$failed failed"; \
	fi; \
	reports=$$(ls $(SAN_DIR)/reports | grep -c -E '^(asan|ubsan)' || true); \
	echo "== ASan/UBSan reports: $$reports (build/sanitize/reports)"
	@$(MAKE) tsan

# tsan: the multi-threaded parts' tests (merge, the coordinator, the hardware state machine,
# the gallery's concurrent writers) built with ThreadSanitizer.
TSAN_TESTS := test_cloud_merge test_scan_assembler test_pattern_sequencer test_pair_connection \
	test_usb_pair_device test_gallery_database
tsan:
	$(call san_build,$(TSAN_TESTS),$(TSAN_DIR),-O1 -g -fsanitize=thread)
	@mkdir -p $(TSAN_DIR)/reports; status=0; \
	for t in $(TSAN_TESTS); do \
	  exe=$$(find $(TSAN_DIR)/devel/lib -name $$t -type f); \
	  TSAN_OPTIONS=halt_on_error=1:log_path=$(TSAN_DIR)/reports/$$t $$exe >$(TSAN_DIR)/$$t.log 2>&1 \
	    && echo "tsan $$t: $$(grep -o '[0-9]* tests\? from .* ran' $(TSAN_DIR)/$$t.log | tail -1) ok" \
	    || { echo "tsan $$t: FAILED (build/tsan/$$t.log)"; status=1; }; \
	done; echo "== TSan reports: $$(ls $(TSAN_DIR)/reports | wc -l) (build/tsan/reports)"; exit $$status

# clean: remove everything built (build/, including devel space, test results, benchmarks).
clean:
	rm -rf $(BUILD_DIR)
