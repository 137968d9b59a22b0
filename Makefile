# Developer entry points for mouse_constraint_ros (plain venv route, no apt ROS needed).
#
#   make venv   create/update .venv (only when requirements/setup files changed)
#   make test   run the test suite with pytest, every tier in turn: unit and ros (a worker per
#               core), the system tests that wait on their processes (two workers per core),
#               then those marked alone, and browser when /usr/bin/chromium is there; each tier
#               runs whatever the one before did, and the last lines sum up every tier
#   make test-unit  only the unit tier (pure code, no rclpy context, no process)
#   make test-browser  only the browser tier (headless chromium on mouse_view)
#   make test-loaded   make test RUNS times (3) while a process keeps a core busy
#   make lint   flake8 (ament_flake8 settings, see .flake8)
#   make run    run the node with config/params.yaml
#   make view   run mouse_view: the body in a browser, dragged with the mouse
#               (VIEW_ARGS='--port 8090' passes options)
#   make bench  run the benchmark suite (python -m bench.run_all): bench/results.md, .json
#   make demo   run the node, grab it, drag a circle, a click jump; record into demo/output/
#   make demo-figure  the same, and the figure replaces the committed demo/figure.png
#   make clean  remove .venv and build artefacts

SHELL := /bin/bash
.DEFAULT_GOAL := test

PYTHON ?= python3
VENV := .venv
VPY := $(VENV)/bin/python
STAMP := $(VENV)/.stamp
REQS := $(wildcard requirements/*.txt)
# pip and uv show their progress: make waits on them.
PIP := $(VPY) -m pip --disable-pip-version-check
# uv installs into .venv (parallel downloads, its own wheel cache, no bytecode compiled). It
# copies from its cache (--link-mode copy): no file of .venv is a hard link that an edit there
# would change in the cache too.
UV_REQ := requirements/installer/uv.txt
UV := $(VENV)/bin/uv pip install --python $(VPY) --link-mode copy
PYTEST_ARGS ?=
# The browser tier's browser: Debian's chromium (apt-get install chromium).
CHROMIUM := /usr/bin/chromium
LINT_PATHS := $(wildcard mouse_constraint_ros test test_support bench launch setup.py)

# If .venv/bin/python is missing or no longer runs (e.g. the base interpreter
# moved), drop the stamp so the venv is (re)built.
ifneq ($(shell $(VPY) -c 'print(1)' 2>/dev/null),1)
$(shell rm -f $(STAMP))
endif

.PHONY: venv test test-unit test-browser test-loaded lint run view bench bench-venv demo \
	demo-figure clean

# For the benchmarks only, the peer engines (PyBullet, MuJoCo) and py-spy: installed into .venv
# by `make bench`, never by `make venv`, `make test` or CI (requirements/bench/ is outside the
# wildcard above).
BENCH_REQS := $(wildcard requirements/bench/*.txt)
BENCH_STAMP := $(VENV)/.bench-stamp
BENCH_ARGS ?=

venv: $(STAMP)

# Reinstall only when a requirements file, setup.py or setup.cfg is newer than
# the stamp. The stamp is touched last, so a failed install is retried next time.
# pip installs the pinned uv, and uv the rest: uv compiles no bytecode (the ROS wheels hold
# thousands of message modules no test imports; Python compiles what is imported on first use
# and keeps it in __pycache__), and its editable install is PEP 660's, which puts the console
# scripts in .venv/bin (never setup.cfg's [develop] script_dir, meant for colcon).
$(STAMP): $(REQS) $(UV_REQ) setup.py setup.cfg
	test -x $(VPY) || $(PYTHON) -m venv $(VENV)
	$(PIP) install -r $(UV_REQ)
	$(UV) $(addprefix -r ,$(REQS))
	$(UV) -e .
	test -x $(VENV)/bin/mouse_constraint_node -a -x $(VENV)/bin/mouse_view || \
	  { echo 'error: .venv/bin/mouse_constraint_node or mouse_view was not installed' >&2; exit 1; }
	touch $@

# The unit and ros tiers run one worker per core (pytest-xdist), each taking whole modules: a
# module's tests share its fixtures and files. Then the system tests that wait on their processes
# (not on the clock) run the same way with two workers per core, whose waits (discovery, a
# lease, a timeout a test asserts) overlap, and they pass with a core kept busy. Last, alone in
# one process, the system and browser tests marked alone (test/conftest.py: the wall clock, a
# recorded burst, a browser rendering in software): under other tests' load a process may miss
# the first messages of a burst. The unit tier's pure tests go to whichever worker is free.
# PARALLEL=, SYSTEM_PARALLEL= and UNIT_PARALLEL= run in one process.
PARALLEL ?= -n auto --dist loadfile
SYSTEM_PARALLEL ?= -n $(shell echo $$(( 2 * $$(nproc) ))) --dist loadfile
UNIT_PARALLEL ?= -n auto

# pytest keeps the test modules it rewrites, and Python the package's bytecode, in __pycache__
# (git ignores it); an environment that forbids writing bytecode would have every pytest process
# compile them again.
unexport PYTHONDONTWRITEBYTECODE

# The tests marked alone take the browser tier along when chromium is there; without it, make
# says so.
HAS_CHROMIUM := $(shell test -x $(CHROMIUM) && echo yes)
ALONE := $(if $(HAS_CHROMIUM),alone or browser,alone and not browser)
NO_BROWSER := browser tier skipped: no $(CHROMIUM)
NO_BROWSER += (apt-get install chromium, then make test-browser)

# Every tier runs, whatever the tiers before it did: each line leaves the tier's exit status and
# JUnit report in $(TIERS), and the last line prints each tier's totals and the failed tests of
# all of them, and fails if any tier failed (test_support/tier_summary.py).
# $(call tier,NAME,MARKERS,OPTIONS): one tier's pytest run.
# -rs: every skipped test is listed with its reason, so a user sees what was not tested and why.
TIERS := $(VENV)/test-tiers
tier = $(VPY) -m pytest test/ -q -rs -m '$(2)' $(3) --junitxml=$(TIERS)/$(1).xml $(PYTEST_ARGS); \
  echo $$? > $(TIERS)/$(1).status
test: venv
	rm -rf $(TIERS); mkdir -p $(TIERS)
	$(call tier,1-unit-ros,not system and not browser,$(PARALLEL))
	$(call tier,2-system,system and not alone,$(SYSTEM_PARALLEL))
	$(if $(HAS_CHROMIUM),,@echo '$(NO_BROWSER)')
	$(call tier,3-$(if $(HAS_CHROMIUM),alone-browser,alone),$(ALONE),)
	$(VPY) -m test_support.tier_summary $(TIERS)

test-browser: venv
	$(VPY) -m pytest test/ -q -m browser $(PYTEST_ARGS)

# The loaded-machine check (docs/reliability.md): every run must pass with a core kept busy.
RUNS ?= 3
test-loaded: venv
	$(VPY) -m test_support.loaded_runs --runs $(RUNS) --hogs 1 -- $(MAKE) --no-print-directory test

test-unit: venv
	$(VPY) -m pytest test/ -q -m unit $(UNIT_PARALLEL) $(PYTEST_ARGS)

lint: venv
	$(VPY) -m flake8 --max-line-length 99 $(LINT_PATHS)

# A long-lived command that Ctrl-C ends: in a terminal, Ctrl-C signals the foreground process
# group, make with the command, and make then dies of SIGINT (exit 130) however the command
# ends. With job control (set -m) the command runs in a process group of its own, the
# terminal's foreground: Ctrl-C reaches it alone and make exits with its status (0). Ctrl-Z
# stops the command, then make with it; fg resumes both. Without a terminal, a plain recipe.
define foreground
if [ -t 0 ]; then set -m; $(1); s=$$?; while [ $$s = 148 ]; do kill -STOP 0; fg >/dev/null; \
  s=$$?; done; exit $$s; else $(1); fi
endef

# The node, the view and the demo's processes run with Fast DDS's participant profile
# config/fast_discovery.xml (they announce themselves every 0.25 s, so a command started beside
# them finds them within 0.4 s, not up to 3 s), unless the environment names one already. Not
# the tests (test/conftest.py sets it) nor the benchmarks (bench.discovery measures it).
DISCOVERY_PROFILE := $(CURDIR)/config/fast_discovery.xml
run view demo demo-figure: export FASTRTPS_DEFAULT_PROFILES_FILE ?= $(DISCOVERY_PROFILE)

# The source tree as an ament prefix in .venv, as colcon's --symlink-install lays one out: the
# package's share/ links config/, launch/, rviz/ and package.xml of the source, and the ament
# index lists the package. make run and make view search it first (AMENT_PREFIX_PATH), so a
# URDF's package://mouse_constraint_ros/ meshes resolve as in an installed workspace.
SHARE := $(VENV)/share/mouse_constraint_ros
$(SHARE)/package.xml: package.xml | $(STAMP)
	mkdir -p $(VENV)/share/ament_index/resource_index/packages $(SHARE)
	touch $(VENV)/share/ament_index/resource_index/packages/mouse_constraint_ros
	for f in config launch rviz package.xml; do ln -sfn $(CURDIR)/$$f $(SHARE)/$$f; done
run view: export AMENT_PREFIX_PATH := $(abspath $(VENV))$(if $(AMENT_PREFIX_PATH),:$(AMENT_PREFIX_PATH))

# URDF=config/tool.urdf: the body is that URDF's link (robot_description, docs/bodies.md), with
# the parameters of the .yaml beside it (config/tool.yaml) over config/params.yaml.
URDF ?=
URDF_PARAMS := $(VENV)/robot_description.yaml
NODE_COMMAND := $(VENV)/bin/mouse_constraint_node --ros-args --params-file config/params.yaml \
  $(if $(URDF),--params-file $(URDF_PARAMS) $(if $(wildcard $(URDF:.urdf=.yaml)),--params-file \
  $(URDF:.urdf=.yaml)))
run: venv $(SHARE)/package.xml
	$(if $(URDF),$(VPY) -m mouse_constraint_ros.cli.urdf_params $(URDF) $(URDF_PARAMS))
	@echo '$(NODE_COMMAND)'
	@$(call foreground,$(NODE_COMMAND))

# VIEW_ARGS: mouse_view's options, e.g. make view VIEW_ARGS='--port 8090'.
VIEW_ARGS ?=
view: venv $(SHARE)/package.xml
	@echo '$(VENV)/bin/mouse_view $(VIEW_ARGS)'
	@$(call foreground,$(VENV)/bin/mouse_view $(VIEW_ARGS))

bench-venv: $(BENCH_STAMP)

$(BENCH_STAMP): $(STAMP) $(BENCH_REQS)
	$(UV) $(addprefix -r ,$(BENCH_REQS))
	touch $@

# From the repository's root, so that bench/ and test_support/ import as packages.
bench: bench-venv
	$(VPY) -m bench.run_all $(BENCH_ARGS)

# The node, mouse_target (a grab, a circle, then a click jump) and mouse_record; see
# demo/run_demo.sh. `make run` must not be running (the demo starts its own node).
demo: venv
	demo/run_demo.sh

demo-figure: venv
	UPDATE_FIGURE=1 demo/run_demo.sh

clean:
	rm -rf $(VENV) build install log .pytest_cache .hypothesis *.egg-info
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
