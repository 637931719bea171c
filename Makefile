# Two entry points (see README):
#   make demo   installs dependencies, builds (Release) and runs `plucker demo`
#   make test   installs dependencies, builds with ASan+UBSan, runs the whole test suite,
#               installs the package and builds the downstream example against it
JOBS ?= $(shell nproc)
RELEASE_DIR ?= build/release
TEST_DIR ?= build/sanitize
PREFIX_DIR ?= build/prefix
# The EuRoC folders examples/vio_euroc is checked on against `plucker vio` (absent: skipped),
# under the sanitizers (downstream: head 10 s, MH_05 clip 40 s wall for the example and the CLI
# together, cold CI machine 2026-12-02) and in Release (vio-euroc-release).
VIO_EUROC_HEAD ?= ../shared/data/euroc-v101-head
VIO_EUROC_DATA ?= $(VIO_EUROC_HEAD) ../shared/data/euroc-mh05-clip
export CCACHE_BASEDIR := $(CURDIR)
export CCACHE_NOHASHDIR := 1

.PHONY: deps release demo test sanitize downstream vio-euroc-release format clean bench python \
  fresh-clone-python

deps:
	./scripts/install_deps.sh

release: deps
	cmake -S . -B $(RELEASE_DIR) -DCMAKE_BUILD_TYPE=Release -DPLUCKER_BUILD_TESTS=OFF
	cmake --build $(RELEASE_DIR) -j $(JOBS)

# The Python package: Release build, installed into PYTHON_PREFIX (docs/python.md).
PYTHON_PREFIX ?= build/prefix-python
python: release
	cmake --install $(RELEASE_DIR) --prefix $(abspath $(PYTHON_PREFIX)) > /dev/null
	@echo "import plucker works with: export PYTHONPATH=$(abspath $(PYTHON_PREFIX))/lib/python3/dist-packages"

# The README's Python set-up on a fresh clone of the committed HEAD, then the LiDAR example
# (tests/fresh_clone_python.sh; a full Release build: run once and record it, not in ctest).
fresh-clone-python:
	nice tests/fresh_clone_python.sh

demo: release
	$(RELEASE_DIR)/apps/plucker/plucker demo --out out/demo

bench: release
	$(RELEASE_DIR)/apps/plucker/plucker bench factors

# -g1: line tables only, enough for file:line in sanitizer reports; full -g made every object
# 4x larger and cost a third more compile time (bundle_adjustment.cc: 11.6 s -> 7.8 s CPU).
sanitize: deps
	cmake -S . -B $(TEST_DIR) -DCMAKE_BUILD_TYPE=Debug -DPLUCKER_SANITIZE=ON \
	  -DPLUCKER_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_FLAGS="-O1" -DCMAKE_CXX_FLAGS_DEBUG="-g1" \
	  -DCMAKE_INSTALL_PREFIX=$(abspath $(PREFIX_DIR))
	cmake --build $(TEST_DIR) -j $(JOBS)

test: sanitize
	cd $(TEST_DIR) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure -j $(JOBS)
	$(MAKE) downstream

downstream:
	cmake --install $(TEST_DIR) --prefix $(abspath $(PREFIX_DIR))
	cmake -S examples/downstream -B build/downstream -DCMAKE_PREFIX_PATH=$(abspath $(PREFIX_DIR)) \
	  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined"
	cmake --build build/downstream -j $(JOBS)
	./build/downstream/downstream_example
	cmake -S examples/vio_euroc -B build/vio_euroc -DCMAKE_PREFIX_PATH=$(abspath $(PREFIX_DIR)) \
	  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined"
	cmake --build build/vio_euroc -j $(JOBS)
	ASAN_OPTIONS=detect_leaks=1 examples/vio_euroc/check.sh build/vio_euroc/vio_euroc \
	  $(abspath $(PREFIX_DIR))/bin/plucker build/vio_euroc/out $(VIO_EUROC_DATA)

# examples/vio_euroc against the installed Release build, on the head and the MH_05 clip.
vio-euroc-release: release
	cmake --install $(RELEASE_DIR) --prefix $(abspath build/prefix-release)
	cmake -S examples/vio_euroc -B build/vio_euroc_release -DCMAKE_BUILD_TYPE=Release \
	  -DCMAKE_PREFIX_PATH=$(abspath build/prefix-release)
	cmake --build build/vio_euroc_release -j $(JOBS)
	examples/vio_euroc/check.sh build/vio_euroc_release/vio_euroc \
	  $(abspath build/prefix-release)/bin/plucker build/vio_euroc_release/out $(VIO_EUROC_DATA)

format:
	find src apps benchmarks examples -name '*.h' -o -name '*.cc' | xargs clang-format -i

clean:
	rm -rf build out
