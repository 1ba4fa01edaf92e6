# The two commands a new user needs: `make demo` and `make test`. Both install what is missing
# (Debian packages), build a Release binary at build/carom and the Python module, then run them or
# the tests. `make demo` also installs the Python module for $(PYTHON).
BUILD ?= build
JOBS ?= $(shell nproc)
# Debian's interpreter: the one with python3-numpy, which the module is built for (the python3
# first on PATH may be another).
PYTHON ?= /usr/bin/python3
# Where python-install puts the package: $(PYTHON)'s site-packages for root (on Debian
# /usr/local/lib/python3.X/dist-packages), else the user's own.
PYTHON_SITE ?= $(shell $(PYTHON) -c 'import os, site, sysconfig; p = sysconfig.get_path("platlib"); print(p if os.access(os.path.dirname(p), os.W_OK) else site.getusersitepackages())')

.PHONY: all deps deps-run build build-run demo test test-sanitize fuzz fuzz-build fuzz-checkpoint fuzz-xyz fuzz-gsd fuzz-plan bench clean format python-install python-uninstall docs-outputs

all: build

deps:
	@scripts/install-deps.sh

deps-run:
	@scripts/install-deps.sh run

# Everything: the binary, the Python module, the tests and the benchmarks.
build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DCAROM_BUILD_TESTS=ON -DCAROM_BUILD_BENCH=ON \
	  > $(BUILD).configure.log 2>&1 || { cat $(BUILD).configure.log; exit 1; }
	@cmake --build $(BUILD) -j $(JOBS)

# The binary and the Python module only, with only their packages: what `make demo` needs. A later
# `make build` or `make test` in the same folder adds the rest.
build-run: deps-run
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DCAROM_BUILD_TESTS=OFF -DCAROM_BUILD_BENCH=OFF \
	  > $(BUILD).configure.log 2>&1 || { cat $(BUILD).configure.log; exit 1; }
	@cmake --build $(BUILD) -j $(JOBS) --target carom carom_python_package

demo: build-run python-install
	$(BUILD)/carom run examples/walls_only.txt 20
	cd /tmp && $(PYTHON) $(CURDIR)/examples/python/quickstart.py

# Makes `import carom` work for $(PYTHON) from any folder.
python-install: build-run
	@test -n "$(PYTHON_SITE)" || { echo "no site-packages folder for $(PYTHON)"; exit 1; }
	@mkdir -p $(PYTHON_SITE)
	@if [ -e $(PYTHON_SITE)/carom ]; then echo "Replacing the carom Python module in $(PYTHON_SITE)/carom"; fi
	@rm -rf $(PYTHON_SITE)/carom
	@cp -r $(BUILD)/python/carom $(PYTHON_SITE)/carom
	@echo "Installed the carom Python module for $(PYTHON) in $(PYTHON_SITE)/carom (make python-uninstall removes it)"

python-uninstall:
	@test -n "$(PYTHON_SITE)" || { echo "no site-packages folder for $(PYTHON)"; exit 1; }
	rm -rf $(PYTHON_SITE)/carom

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

# Rewrites the outputs README.md and docs/*.md show after `$ ` commands to what $(BUILD)/carom
# and the Python module print now (ctest documented_commands_run compares them). Needs a build.
docs-outputs:
	$(PYTHON) tests/docs_commands.py --update . $(BUILD)/carom $(BUILD)/python

# The whole suite under AddressSanitizer and UndefinedBehaviorSanitizer (any report fails it).
SANITIZE = -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
test-sanitize: deps
	@cmake -S . -B $(BUILD)-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAROM_BUILD_BENCH=OFF -DCAROM_BUILD_PYTHON=OFF \
	  -DCMAKE_CXX_FLAGS="$(SANITIZE)" -DCMAKE_EXE_LINKER_FLAGS="$(SANITIZE)" > $(BUILD)-sanitize.configure.log 2>&1 \
	  || { cat $(BUILD)-sanitize.configure.log; exit 1; }
	@cmake --build $(BUILD)-sanitize -j $(JOBS)
	ctest --test-dir $(BUILD)-sanitize --output-on-failure -j $(JOBS) -LE long

# libFuzzer on a reader, with AddressSanitizer and UndefinedBehaviorSanitizer; FUZZ_SECONDS long.
# `make fuzz` fuzzes the classic input reader (and a few events of both engines on what it
# accepts), `make fuzz-checkpoint` the checkpoint reader (resuming what it accepts for a few
# events under the invariant check), `make fuzz-xyz` carom view's extended-XYZ reader (and the
# page made of what it reads), `make fuzz-plan` the sweep's plan reader (and the commands, tables
# and report of what it accepts). New crashes land in build-fuzz/; copy them into the reader's
# regressions folder (tests/fuzz/regressions, tests/fuzz/checkpoint/regressions,
# tests/fuzz/xyz/regressions, tests/fuzz/plan/regressions), which `make test` replays.
FUZZ_SECONDS ?= 300
FUZZ_FLAGS = -max_total_time=$(FUZZ_SECONDS) -timeout=10 -rss_limit_mb=2048
fuzz-build: deps
	@cmake -S . -B $(BUILD)-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
	  -DCAROM_FUZZ=ON -DCAROM_BUILD_TESTS=OFF -DCAROM_BUILD_BENCH=OFF -DCAROM_BUILD_PYTHON=OFF \
	  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=all" \
	  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > $(BUILD)-fuzz.configure.log 2>&1 \
	  || { cat $(BUILD)-fuzz.configure.log; exit 1; }
	@cmake --build $(BUILD)-fuzz -j $(JOBS) --target carom_fuzz_classic_input carom_fuzz_checkpoint carom_fuzz_xyz carom_fuzz_gsd \
	  carom_fuzz_plan

fuzz: fuzz-build
	mkdir -p $(BUILD)-fuzz/corpus
	cd $(BUILD)-fuzz && ./carom_fuzz_classic_input $(FUZZ_FLAGS) -max_len=4096 \
	  corpus ../tests/fuzz/corpus

fuzz-checkpoint: fuzz-build
	mkdir -p $(BUILD)-fuzz/corpus-checkpoint
	cd $(BUILD)-fuzz && ./carom_fuzz_checkpoint $(FUZZ_FLAGS) -max_len=16384 \
	  corpus-checkpoint ../tests/fuzz/checkpoint/corpus

fuzz-xyz: fuzz-build
	mkdir -p $(BUILD)-fuzz/corpus-xyz
	cd $(BUILD)-fuzz && ./carom_fuzz_xyz $(FUZZ_FLAGS) -max_len=8192 \
	  corpus-xyz ../tests/fuzz/xyz/corpus

fuzz-gsd: fuzz-build
	mkdir -p $(BUILD)-fuzz/corpus-gsd
	cd $(BUILD)-fuzz && ./carom_fuzz_gsd $(FUZZ_FLAGS) -max_len=16384 \
	  corpus-gsd ../tests/fuzz/gsd/corpus

fuzz-plan: fuzz-build
	mkdir -p $(BUILD)-fuzz/corpus-plan
	cd $(BUILD)-fuzz && ./carom_fuzz_plan $(FUZZ_FLAGS) -max_len=4096 -dict=../tests/fuzz/plan/plan.dict \
	  corpus-plan ../tests/fuzz/plan/corpus

# Collisions per second and bytes per disk, N = 10^3..10^6 (about 5 minutes on 2 cores).
bench: build
	$(BUILD)/carom_micro_bench --benchmark_min_time=0.2
	$(PYTHON) bench/run_bench.py --carom $(BUILD)/carom

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD) $(BUILD).configure.log $(BUILD)-sanitize $(BUILD)-sanitize.configure.log
