# occlusion_env: two commands on a fresh Debian 12 machine.
#   make demo   install what is missing, build, run the main job on the embedded objects
#   make test   install what is missing, build, run every test; non-zero exit on any failure
# Python is pinned to Debian's own interpreter: a pyenv python3 first on PATH breaks catkin.

WS        := .build_ws
BUILD     := $(WS)/build
DEVEL     := $(WS)/devel
JOBS      ?= $(shell nproc)
SYS_PATH  := /usr/bin:/bin:/usr/sbin:/sbin:$(PATH)
CATKIN    := env PATH=$(SYS_PATH) catkin_make -C $(WS) -j$(JOBS) \
             -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
             -DCMAKE_BUILD_TYPE=Release
IN_WS     := env PATH=$(SYS_PATH) bash -c 'source $(DEVEL)/setup.bash && "$$@"' --
DEMO_OUT  ?= output/demo

.PHONY: deps build demo test bench format clean

deps:
	@bash scripts/install_deps.sh

$(WS)/src/occlusion_env:
	@mkdir -p $(WS)/src
	@ln -sfn ../.. $(WS)/src/occlusion_env

build: deps $(WS)/src/occlusion_env
	$(CATKIN)

demo: build
	@bash scripts/demo.sh

test: build
	$(CATKIN) tests
	@bash scripts/run_tests.sh $(BUILD)

bench: build
	$(CATKIN) occlusion_bench occlusion_learning_bench
	$(IN_WS) $(DEVEL)/lib/occlusion_env/occlusion_bench
	$(IN_WS) $(DEVEL)/lib/occlusion_env/occlusion_learning_bench

format:
	@find include src test bench -name '*.hpp' -o -name '*.cpp' | xargs clang-format -i

clean:
	rm -rf $(WS)
