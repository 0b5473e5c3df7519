# voronoid -- build, run, test, bench.
#
#   make            release build into build/ (libvor.a, voronoi, voronoid)
#   make run        build and start the service on 127.0.0.1:8080
#                   (PORT=N another port, ARGS='...' more voronoid flags)
#   make test       sanitizer build (ASan+UBSan) into build/asan/, every test
#   make python-client  the Python client against a daemon and scipy
#   make tsan       the server's tests under ThreadSanitizer (make test runs it)
#   make bench      benchmark tables and plots into build/bench/
#   make soak       ten minutes of mixed and hostile load (SOAK_SECONDS=60
#                   for a short run); not part of make test
#   make deps       install missing Debian packages (root), or say how
#
# Sources are found by wildcard: core/*.c -> libvor, api/*.c api/*.cc ->
# libvorapi, cli/*.c -> voronoi, server/*.c -> voronoid, tests/<area>/test_*.c
# -> one cmocka binary each. Adding a file needs no edit here.

SHELL := /bin/bash
# B is the output directory: parallel builds of one tree can use their own.
# Set before any rule names it: make expands prerequisites as it reads them.
B ?= build
CC ?= gcc
ifeq ($(origin CC),default)
CC := gcc
endif
CXX := g++
PKG := pkg-config

# Debian packages the build and the tests need (make deps installs them).
DEPS_BUILD := pkg-config gcc g++ make libgmp-dev libjansson-dev \
              libmicrohttpd-dev libcmocka-dev libcurl4-openssl-dev zlib1g-dev \
              libfast-float-dev libdragonbox-dev
# python3-numpy, python3-scipy: the Python client's test, run with Debian's
# /usr/bin/python3 whatever python3 comes first on PATH.
DEPS_TEST := curl chromium nginx-light python3-numpy python3-scipy
# node and npm: the machine's own if it has them (a NodeSource build bundles
# npm and conflicts with Debian's npm package), Debian's otherwise.
DEPS_NODE := $(if $(shell command -v npm),,nodejs npm)
# bench: CGAL, Boost.Polygon and qhull are the peers the algorithms are
# compared with (delaunator and d3-delaunay come from npm); wrk loads the
# service; gnuplot draws the plots.
DEPS_BENCH := libcgal-dev libboost-dev libqhull-dev wrk gnuplot-nox curl

WARN := -Wall -Wextra -Wpedantic -Wshadow -Wstrict-prototypes \
        -Wmissing-prototypes -Werror
BASE_CFLAGS := -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE \
               -ffp-contract=off -fno-fast-math -g $(WARN)
BASE_CXXFLAGS := -std=c++17 -ffp-contract=off -g -Wall -Wextra -Werror
DRAGONBOX_CFLAGS := -I/usr/include/dragonbox-1.1.3

release_FLAGS := -O2 -DNDEBUG
asan_FLAGS := -O1 -fsanitize=address,undefined -fno-sanitize-recover=all \
              -fno-omit-frame-pointer
tsan_FLAGS := -O1 -fsanitize=thread -fno-omit-frame-pointer

pc = $(shell $(PKG) --cflags $(1) 2>/dev/null)
pl = $(shell $(PKG) --libs $(1) 2>/dev/null)

CORE_LIBS = $(call pl,gmp) -lm
API_CFLAGS = $(call pc,jansson) $(DRAGONBOX_CFLAGS)
API_LIBS = $(call pl,jansson) $(call pl,zlib) -lstdc++
SRV_CFLAGS = $(call pc,libmicrohttpd) $(call pc,zlib)
SRV_LIBS = $(call pl,libmicrohttpd) -lpthread
TEST_CFLAGS = $(call pc,cmocka) $(call pc,libcurl)
TEST_LIBS = $(call pl,cmocka) $(call pl,libcurl)

CORE_SRC := $(wildcard core/*.c)
API_SRC := $(wildcard api/*.c)
API_CXX := $(wildcard api/*.cc)
CLI_SRC := $(wildcard cli/*.c)
SRV_SRC := $(wildcard server/*.c)
SRV_LIB_SRC := $(filter-out server/main.c,$(SRV_SRC))
# The test support library also carries api/distribution.c (libc and libm
# only), so that the core tests generate the service's own distributions
# without linking the codec.
SUPPORT_SRC := $(wildcard tests/support/*.c) api/distribution.c
TESTS_CORE := $(wildcard tests/core/test_*.c)
TESTS_API := $(wildcard tests/api/test_*.c) $(wildcard tests/cli/test_*.c)
TESTS_SRV := $(wildcard tests/server/test_*.c)
TESTS_INT := $(wildcard tests/integration/test_*.c)

.PHONY: all run test tsan bench deps deps-test deps-bench clean unit \
        integration browser deploy-test openapi-lint check-deps fuzz \
        fuzz-quick python-client
.DELETE_ON_ERROR:

all: deps $(B)/voronoi $(B)/voronoid

# ---- one variant of everything (release, asan, tsan) ---------------------
# $(1) = variant name, $(2) = output directory
define VARIANT
$(2)/%.o: %.c | check-deps
	@mkdir -p $$(@D)
	$$(CC) $$(BASE_CFLAGS) $$($(1)_FLAGS) $$(API_CFLAGS) $$(SRV_CFLAGS) \
	    $$(TEST_CFLAGS) -MMD -MP -c $$< -o $$@
$(2)/%.o: %.cc | check-deps
	@mkdir -p $$(@D)
	$$(CXX) $$(BASE_CXXFLAGS) $$($(1)_FLAGS) $$(DRAGONBOX_CFLAGS) -MMD -MP \
	    -c $$< -o $$@
$(2)/libvor.a: $$(CORE_SRC:%.c=$(2)/%.o)
	@mkdir -p $$(@D); rm -f $$@; $$(if $$^,ar rcs $$@ $$^,printf '!<arch>\n' > $$@)
$(2)/libvorapi.a: $$(API_SRC:%.c=$(2)/%.o) $$(API_CXX:%.cc=$(2)/%.o)
	@mkdir -p $$(@D); rm -f $$@; $$(if $$^,ar rcs $$@ $$^,printf '!<arch>\n' > $$@)
$(2)/libvorsrv.a: $$(SRV_LIB_SRC:%.c=$(2)/%.o)
	@mkdir -p $$(@D); rm -f $$@; $$(if $$^,ar rcs $$@ $$^,printf '!<arch>\n' > $$@)
$(2)/libvortest.a: $$(SUPPORT_SRC:%.c=$(2)/%.o)
	@mkdir -p $$(@D); rm -f $$@; $$(if $$^,ar rcs $$@ $$^,printf '!<arch>\n' > $$@)
$(2)/voronoi: $$(CLI_SRC:%.c=$(2)/%.o) $(2)/libvorapi.a $(2)/libvor.a
	$$(CC) $$($(1)_FLAGS) $$^ -o $$@ $$(API_LIBS) $$(CORE_LIBS)
$(2)/voronoid: $(2)/server/main.o $(2)/libvorsrv.a $(2)/libvorapi.a \
               $(2)/libvor.a
	$$(CC) $$($(1)_FLAGS) $$^ -o $$@ $$(SRV_LIBS) $$(API_LIBS) $$(CORE_LIBS)
$(2)/tests/core/%: $(2)/tests/core/%.o $(2)/libvortest.a $(2)/libvor.a
	$$(CC) $$($(1)_FLAGS) $$^ -o $$@ $$(TEST_LIBS) $$(CORE_LIBS)
$(2)/tests/api/%: $(2)/tests/api/%.o $(2)/libvortest.a $(2)/libvorapi.a \
                  $(2)/libvor.a
	$$(CC) $$($(1)_FLAGS) $$^ -o $$@ $$(TEST_LIBS) $$(API_LIBS) $$(CORE_LIBS)
$(2)/tests/cli/%: $(2)/tests/cli/%.o $(2)/libvortest.a $(2)/libvorapi.a \
                  $(2)/libvor.a
	$$(CC) $$($(1)_FLAGS) $$^ -o $$@ $$(TEST_LIBS) $$(API_LIBS) $$(CORE_LIBS)
$(2)/tests/server/%: $(2)/tests/server/%.o $(2)/libvortest.a \
                     $(2)/libvorsrv.a $(2)/libvorapi.a $(2)/libvor.a
	$$(CC) $$($(1)_FLAGS) $$^ -o $$@ $$(TEST_LIBS) $$(SRV_LIBS) \
	    $$(API_LIBS) $$(CORE_LIBS)
$(2)/tests/integration/%: $(2)/tests/integration/%.o $(2)/libvortest.a \
                          $(2)/libvorapi.a $(2)/libvor.a
	$$(CC) $$($(1)_FLAGS) $$^ -o $$@ $$(TEST_LIBS) $$(API_LIBS) \
	    $$(CORE_LIBS)
endef

$(eval $(call VARIANT,release,$(B)))
$(eval $(call VARIANT,asan,$(B)/asan))
$(eval $(call VARIANT,tsan,$(B)/tsan))

-include $(shell find $(B) -name '*.d' 2>/dev/null)

# ---- embedded web assets (owned by server/) ------------------------------
# voronoid serves the page (the files in web/) and openapi.yaml from its own
# binary: server/embed.sh writes them as byte arrays into <variant>/gen/
# embedded.c (rewritten only when they change, so it is run every time and
# the object is rebuilt only then), and every variant archives the object
# into its libvorsrv.a.
EMBED_FILES = $(sort $(wildcard web/*)) $(wildcard openapi.yaml)
.PHONY: embed-force
embed-force: ;
define EMBED
$(1)/gen/embedded.c: server/embed.sh embed-force
	@mkdir -p $$(@D)
	@sh server/embed.sh $$@ $$(EMBED_FILES)
$(1)/gen/embedded.o: $(1)/gen/embedded.c server/assets.h | check-deps
	$$(CC) $$(BASE_CFLAGS) $$($(2)_FLAGS) -I. -c $$< -o $$@
$(1)/libvorsrv.a: $(1)/gen/embedded.o
endef
$(eval $(call EMBED,$(B),release))
$(eval $(call EMBED,$(B)/asan,asan))
$(eval $(call EMBED,$(B)/tsan,tsan))
# ---- end of embedded web assets -------------------------------------------

tbin = $(patsubst %.c,$(1)/%,$(2))

# ---- run -----------------------------------------------------------------
# make run PORT=9000 ARGS='--workers 1': PORT becomes --port only when
# given, so that VORONOID_PORT (and every other VORONOID_* variable) in the
# environment still counts; voronoid's own defaults are 127.0.0.1:8080.
PORT ?=
ARGS ?=
run: all
	./$(B)/voronoid$(if $(PORT), --port $(PORT))$(if $(ARGS), $(ARGS))

# ---- tests ---------------------------------------------------------------
# Every test binary runs even when one fails; the target fails at the end
# if any did.
ASAN_ENV := ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:halt_on_error=1 \
            UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

UNIT_BINS = $(call tbin,$(B)/asan,$(TESTS_CORE) $(TESTS_API) $(TESTS_SRV))
INT_BINS = $(call tbin,$(B)/asan,$(TESTS_INT))

unit: deps $(UNIT_BINS) $(B)/asan/voronoi
	@fail=0; for t in $(UNIT_BINS); do \
	    echo "== $$t"; \
	    $(ASAN_ENV) VOR_CLI=$(B)/asan/voronoi ./$$t || fail=1; \
	done; exit $$fail

integration: deps $(INT_BINS) $(B)/asan/voronoid
	@fail=0; for t in $(INT_BINS); do \
	    echo "== $$t"; \
	    $(ASAN_ENV) VOR_DAEMON=$(B)/asan/voronoid ./$$t || fail=1; \
	done; exit $$fail

TSAN_BINS = $(call tbin,$(B)/tsan,$(TESTS_SRV) $(TESTS_INT))
tsan: deps $(TSAN_BINS) $(B)/tsan/voronoid
	@fail=0; for t in $(TSAN_BINS); do \
	    echo "== $$t (tsan)"; \
	    TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
	    VOR_DAEMON=$(B)/tsan/voronoid VOR_TSAN=1 ./$$t || fail=1; \
	done; exit $$fail

# Browser, OpenAPI and deploy tests live in tests/<name>/run (executable);
# each is skipped only if it does not exist yet.
browser openapi-lint deploy-test: deps-test all
	@d=tests/$(subst -test,,$(subst -lint,,$@)); \
	if [ -x $$d/run ]; then $$d/run; else echo "$$d/run: none"; fi

# The Python client (clients/python) against a sanitizer-built daemon,
# checked against scipy.spatial and the service's own JSON.
PYTHON_TEST := /usr/bin/python3
python-client: deps deps-test $(B)/asan/voronoid
	$(ASAN_ENV) VOR_DAEMON=$(B)/asan/voronoid \
	    $(PYTHON_TEST) clients/python/test_voronoid.py

test: deps deps-test
	@fail=0; failed=; \
	for t in unit integration tsan fuzz-quick openapi-lint browser \
	         deploy-test python-client; do \
	    $(MAKE) --no-print-directory $$t || { fail=1; failed="$$failed $$t"; }; \
	done; \
	if [ $$fail = 0 ]; then echo "make test: all passed"; \
	else echo "make test: FAILED:$$failed"; fi; exit $$fail

# ---- soak (not part of make test) -----------------------------------------
# Ten minutes (SOAK_SECONDS) of mixed and hostile load against the ASan
# build; prints requests by status, p50/p99, RSS, resets and sanitizer
# reports (tests/soak/soak.py; its other scenarios measure the targets of
# the slow-client and memory work: --scenario nonreaders|slowloris|sigterm).
.PHONY: soak
SOAK_SECONDS ?= 600
soak: deps $(B)/asan/voronoid
	SOAK_SECONDS=$(SOAK_SECONDS) VOR_DAEMON=$(B)/asan/voronoid \
	    python3 tests/soak/soak.py --scenario mixed

# ---- bench ---------------------------------------------------------------
# Owned by bench/. bench/run builds the drivers (make bench-bins, each peer
# on its own so that one missing library skips one peer) and writes tables,
# CSV and plots into $(B)/bench/. BENCH_QUICK=1 bench/run: small sizes only.
BENCH_BIN = $(B)/bench/bin
# The peers are built with the release library's optimisation, no more.
BENCH_OPT := -O2 -DNDEBUG
BENCH_PEERS = $(BENCH_BIN)/peer_cgal $(BENCH_BIN)/peer_boost \
              $(BENCH_BIN)/peer_qhull

.PHONY: bench-bins bench-peers
bench: deps deps-bench all
	@if [ -x bench/run ]; then B=$(B) bench/run; else echo "bench/run: none"; fi

bench-bins: $(BENCH_BIN)/bench_algo $(BENCH_BIN)/mhd_baseline
bench-peers: $(BENCH_PEERS)

$(BENCH_BIN)/bench_algo: bench/bench_algo.c bench/bench_util.h bench/bench_shapes.h \
                         $(B)/libvortest.a $(B)/libvorapi.a $(B)/libvor.a
	@mkdir -p $(@D)
	$(CC) $(BASE_CFLAGS) $(BENCH_OPT) $< $(B)/libvortest.a $(B)/libvorapi.a \
	    $(B)/libvor.a -o $@ $(API_LIBS) $(CORE_LIBS)
$(BENCH_BIN)/mhd_baseline: bench/mhd_baseline.c
	@mkdir -p $(@D)
	$(CC) $(BASE_CFLAGS) $(BENCH_OPT) $(call pc,libmicrohttpd) $< -o $@ \
	    $(call pl,libmicrohttpd)
$(BENCH_BIN)/peer_cgal: bench/peer_cgal.cc bench/bench_util.h
	@mkdir -p $(@D)
	$(CXX) -std=c++17 $(BENCH_OPT) -DCGAL_NDEBUG -Wall -Wextra $< -o $@ \
	    -lgmp -lmpfr
$(BENCH_BIN)/peer_boost: bench/peer_boost.cc bench/bench_util.h
	@mkdir -p $(@D)
	$(CXX) -std=c++17 $(BENCH_OPT) -Wall -Wextra $< -o $@
$(BENCH_BIN)/peer_qhull: bench/peer_qhull.c bench/bench_util.h
	@mkdir -p $(@D)
	$(CC) $(BASE_CFLAGS) $(BENCH_OPT) $< -o $@ -lqhull_r -lm

# ---- fuzzing (libFuzzer) ------------------------------------------------
# make fuzz: each tests/fuzz/fuzz_*.c target runs FUZZ_SECONDS under ASan and
# UBSan with clang's libFuzzer; a failing input is saved in $(B)/fuzz/ and
# fails the target. make test runs a short deterministic round (fuzz-quick).
FUZZ_SECONDS ?= 60
FUZZ_CC := clang
FUZZ_FLAGS := -g -O1 -fsanitize=address,undefined -fno-sanitize-recover=all \
              -ffp-contract=off
FUZZ_TARGETS := $(patsubst tests/fuzz/%.c,$(B)/fuzz/%,$(wildcard tests/fuzz/fuzz_*.c))

$(B)/fuzz/numconv.o: $(API_CXX)
	@mkdir -p $(@D)
	clang++ -std=c++17 $(FUZZ_FLAGS) -fsanitize=fuzzer-no-link \
	    $(DRAGONBOX_CFLAGS) -c $(API_CXX) -o $@
$(B)/fuzz/%: tests/fuzz/%.c $(CORE_SRC) $(API_SRC) $(B)/fuzz/numconv.o | deps
	@mkdir -p $(@D)
	$(FUZZ_CC) -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE \
	    $(FUZZ_FLAGS) -fsanitize=fuzzer $(API_CFLAGS) $< $(CORE_SRC) \
	    $(API_SRC) $(B)/fuzz/numconv.o -o $@ $(API_LIBS) $(CORE_LIBS)

# FUZZ_LIMIT and FUZZ_CORPUS let make test run a deterministic round: a
# fixed seed, a fixed number of inputs and no corpus carried between runs.
FUZZ_LIMIT ?= -max_total_time=$(FUZZ_SECONDS)
FUZZ_CORPUS ?= corpus
fuzz: $(FUZZ_TARGETS)
	@fail=0; for t in $(FUZZ_TARGETS); do \
	    echo "== $$t ($(FUZZ_LIMIT))"; \
	    corpus=; if [ -n "$(FUZZ_CORPUS)" ]; then \
	        corpus=$$t.$(FUZZ_CORPUS); mkdir -p $$corpus; fi; \
	    ASAN_OPTIONS=detect_leaks=1 $$t $(FUZZ_LIMIT) -seed=1 \
	        -print_final_stats=1 -artifact_prefix=$$t- $$corpus \
	        2>$$t.log || { fail=1; grep -A12 -E 'ERROR|fuzz_[a-z]+:' $$t.log \
	            | head -40; }; \
	    grep -E '^stat::number_of_executed_units' $$t.log; \
	done; exit $$fail

# The round make test runs.
fuzz-quick:
	@$(MAKE) --no-print-directory fuzz FUZZ_LIMIT=-runs=40000 FUZZ_CORPUS=

# ---- dependencies --------------------------------------------------------
# dpkg tells what is installed; apt-get installs the rest when we are root.
define INSTALL_MISSING
	@missing=$$(for p in $(1); do \
	    dpkg-query -W -f='$${Status}' $$p 2>/dev/null | \
	        grep -q 'install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	    if [ "$$(id -u)" = 0 ]; then \
	        echo "installing:" $$missing; \
	        export DEBIAN_FRONTEND=noninteractive; \
	        apt-get update -qq && apt-get install -y -qq $$missing \
	            >/dev/null || exit 1; \
	    else \
	        echo "missing Debian packages; run as root:"; \
	        echo "  apt-get update && apt-get install -y" $$missing; \
	        exit 1; \
	    fi; \
	fi
endef

deps:
	$(call INSTALL_MISSING,$(DEPS_BUILD))
deps-test:
	$(call INSTALL_MISSING,$(DEPS_TEST) $(DEPS_NODE))
deps-bench:
	$(call INSTALL_MISSING,$(DEPS_BENCH) $(DEPS_NODE))

check-deps: ;

clean:
	rm -rf $(B)
