# The two commands a new user needs: `make demo` and `make test`. Both install what is missing
# (Debian packages), build a Release binary at build/carom, then run it or the tests.
BUILD ?= build
JOBS ?= $(shell nproc)

.PHONY: all deps build demo test clean format

all: build

deps:
	@scripts/install-deps.sh

build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release > $(BUILD).configure.log 2>&1 || { cat $(BUILD).configure.log; exit 1; }
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	$(BUILD)/carom run examples/walls_only.txt 20

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD) $(BUILD).configure.log
