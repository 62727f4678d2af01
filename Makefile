# sumi: a scene-language interpreter for stylised rendering.
# Hand-written; every target is listed in `make help`.

CC      ?= gcc
CXX     ?= g++
BUILD   ?= build
SUMI_SHARED ?= ../shared
export SUMI_SHARED

WARN    := -Wall -Wextra -Wshadow -Wstrict-prototypes -Wmissing-prototypes \
           -Wpointer-arith -Wformat=2 -Wundef -Wvla -Wno-unused-parameter
# Float code runs in SIMD lanes where a loop allows (the shading's square
# roots and divisions): sumi reads no errno and traps no FP exception, and
# lanes give the same IEEE results as one value at a time.
VECTOR  := -fno-math-errno -fno-trapping-math -fvect-cost-model=cheap
CFLAGS  ?= -O2 -g
# Headers of the Debian libraries that keep theirs in a folder of their own.
INCLUDES := -I/usr/include/libxml2 -I/usr/include/freetype2 -I/usr/include/harfbuzz
CFLAGS  += -std=c11 -D_DEFAULT_SOURCE $(WARN) $(VECTOR) -MMD -MP -pthread $(INCLUDES)
CXXFLAGS ?= -O2 -g
CXXFLAGS += -std=c++17 -Wall -Wextra -MMD -MP -fPIC
# The 2D bridge: Clipper's header, and CGAL's interval arithmetic, which
# needs the rounding mode honoured (its start-up check of it is off, as
# valgrind, for make valgrind, does not emulate rounding modes).
P2D_FLAGS := -I/usr/include/polyclipping -frounding-math -DCGAL_DISABLE_ROUNDING_MATH_CHECK -DCGAL_ALWAYS_ROUND_TO_NEAREST
LDLIBS  := -lxml2 -lpotrace -lpng16 -lcjson -losdCPU -lassimp -lpolyclipping -lgmp -lmpfr \
           -lharfbuzz -lfontconfig -lfreetype -ldl -lm -pthread -lstdc++

ifeq ($(SANITIZE),1)
BUILD   := build/san
# float-cast-overflow is not in gcc's `undefined` group: a double beyond
# the range of the integer it becomes (a range's element count) is UB too.
SAN     := -fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer \
           -fno-sanitize-recover=undefined,float-cast-overflow
CFLAGS  += $(SAN)
CXXFLAGS += $(SAN)
LDFLAGS += $(SAN)
endif

CORE_C   := $(filter-out src/main.c,$(wildcard src/*/*.c))
# The C++ bridges behind C headers (the image bridge is a library of its own).
CORE_CXX := $(filter-out src/io/image_oiio.cpp,$(wildcard src/*/*.cpp))
CORE_OBJ := $(CORE_C:%.c=$(BUILD)/%.o) $(CORE_CXX:%.cpp=$(BUILD)/%.o)
MAIN_OBJ := $(BUILD)/src/main.o
OIIO_LIB := $(BUILD)/libsumi_oiio.so
UNIT_SRC := $(wildcard tests/unit/test_*.c)
UNIT_BIN := $(UNIT_SRC:tests/unit/%.c=$(BUILD)/unit/%)
TOOLS    := $(BUILD)/imgcmp

DEBIAN_PACKAGES := gcc g++ make pkg-config libopenimageio-dev libosd-dev libcjson-dev libpng-dev \
                   libassimp-dev libxml2-dev libpotrace-dev librsvg2-bin clang libclang-rt-14-dev \
                   assimp-testmodels python3-skimage libpolyclipping-dev libcgal-dev libgmp-dev libmpfr-dev \
                   libfreetype-dev libharfbuzz-dev libfontconfig-dev fonts-dejavu-core fonts-noto-cjk \
                   openscad python3-numpy

.PHONY: all deps test test-unit test-slurm test-gallery update-snapshots update-golden fuzz valgrind bench bench-parse \
        bench-eval bench-solve bench-tiles bench-bigmesh bench-orbit bench-csg gallery clean help example install check-cp

all: $(BUILD)/sumi $(OIIO_LIB) $(BUILD)/stdlib

$(BUILD)/sumi: $(CORE_OBJ) $(MAIN_OBJ)
	$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

# The OpenImageIO bridge is a shared library loaded on first use, so the
# commands that touch no image do not pay OIIO's start-up (~0.2 s, 130 MB).
$(OIIO_LIB): src/io/image_oiio.cpp src/io/image_oiio.h
	@mkdir -p $(dir $@)
	$(CXX) $(CXXFLAGS) -shared -o $@ $< -lOpenImageIO -lOpenImageIO_Util $(LDFLAGS)

# stdlib/ sits beside the binary so an uninstalled build finds it.
$(BUILD)/stdlib:
	@mkdir -p $(BUILD)
	ln -sfn $(CURDIR)/stdlib $@

$(BUILD)/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -c -o $@ $<

$(BUILD)/%.o: %.cpp
	@mkdir -p $(dir $@)
	$(CXX) $(CXXFLAGS) -c -o $@ $<

$(BUILD)/src/geom/poly2d_bridge.o $(BUILD)/src/geom/csg_bridge.o: CXXFLAGS += $(P2D_FLAGS)

$(BUILD)/unit/%: tests/unit/%.c tests/unit/unit.h $(CORE_OBJ) | $(OIIO_LIB) $(BUILD)/stdlib
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $< $(CORE_OBJ) $(LDLIBS)

$(BUILD)/imgcmp: tests/tools/imgcmp.c $(CORE_OBJ) | $(OIIO_LIB)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $< $(CORE_OBJ) $(LDLIBS)

# Install the Debian packages the build, the tests and the peers need.
deps:
	@missing=""; for p in $(DEBIAN_PACKAGES) $(PEER_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=""; else SUDO=sudo; fi; \
	  $$SUDO apt-get update -q && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -q --no-install-recommends $$missing; \
	else echo "all packages present"; fi

PEER_PACKAGES ?=
bench bench-parse bench-eval: PEER_PACKAGES := povray openscad hyperfine python3 time python3-opencv
bench-solve: PEER_PACKAGES := nodejs python3

# The README's first command: install, build, and render the default example.
example: deps all
	$(BUILD)/sumi render examples/teapot_toon.npr -o teapot_toon.png

test: deps all $(UNIT_BIN) $(TOOLS)
	@BUILD=$(BUILD) sh tests/run.sh

# Regenerate parse/error/eval snapshots after a deliberate change; read the diff.
update-snapshots: all
	@BUILD=$(BUILD) UPDATE=1 sh tests/run.sh

update-golden: all $(TOOLS)
	@BUILD=$(BUILD) UPDATE_GOLDEN=1 sh tests/run.sh

# libFuzzer targets (tests/fuzz/fuzz_*.c): the parser, the evaluator, FOLD
# import, mesh import and image reading, each over the whole core built by
# clang under ASan and UBSan, float-cast-overflow included. Each starts
# from a seed corpus of the tests' own files and runs FUZZ_SECONDS
# (`make fuzz` runs them all, one after the other; FUZZ_TARGETS picks some).
FUZZ_SECONDS ?= 60
# One allocation may be up to 2.5 GB: sumi's own are bounded by its limits
# (an image's float copy: 1 GiB), but OpenEXR allocates some header fields
# at the size a 32-bit count in the header states (under 2 GiB, never
# touched: the read fails at the file's end). Anything larger is a finding.
FUZZ_MALLOC_MB ?= 2560
FUZZ_DIR     := build/fuzz
FUZZ_TARGETS ?= parse eval fold mesh image
FUZZ_SAN     := -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all
FUZZ_CFLAGS  := -std=c11 -D_DEFAULT_SOURCE $(INCLUDES) -g -O1 -pthread $(FUZZ_SAN) -fsanitize=fuzzer-no-link
FUZZ_OBJ     := $(CORE_C:%.c=$(FUZZ_DIR)/%.o) $(CORE_CXX:%.cpp=$(FUZZ_DIR)/%.o)
FUZZ_BIN     := $(FUZZ_TARGETS:%=$(FUZZ_DIR)/fuzz_%)
# Seeds: the text a target reads, from the tests (meshes also from
# assimp-testmodels' OBJ folder when installed).
FUZZ_SEEDS_parse := tests/parse/*.npr tests/errors/*.npr
# tests/render/csg_blocks.npr is left out: its CGAL corefinement of fine
# spheres takes 90 s under the sanitizers, past the 20 s a unit may take
# (tests/eval/csg_blocks.npr seeds the CSG paths at a smaller size).
FUZZ_SEEDS_eval  := $(filter-out tests/render/csg_blocks.npr,$(wildcard tests/eval/*.npr tests/errors/*.npr tests/render/*.npr examples/*.npr))
FUZZ_SEEDS_fold  := tests/data/fold/*.fold
FUZZ_SEEDS_mesh  := tests/render/*.obj $(wildcard /usr/share/assimp/models/OBJ/*.obj)
FUZZ_SEEDS_image := tests/data/image/*

$(FUZZ_DIR)/%.o: %.c
	@mkdir -p $(dir $@)
	clang $(FUZZ_CFLAGS) -c -o $@ $<

$(FUZZ_DIR)/%.o: %.cpp
	@mkdir -p $(dir $@)
	clang++ -std=c++17 $(P2D_FLAGS) -g -O1 $(FUZZ_SAN) -fsanitize=fuzzer-no-link -c -o $@ $<

$(FUZZ_DIR)/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz_common.h $(FUZZ_OBJ)
	clang $(FUZZ_CFLAGS) -c -o $@.o $<
	clang++ $(FUZZ_SAN) -fsanitize=fuzzer -o $@ $@.o $(FUZZ_OBJ) $(LDLIBS)

.SECONDARY: $(FUZZ_OBJ)

# image reading loads the OpenImageIO bridge from beside the binary
$(FUZZ_DIR)/libsumi_oiio.so: $(OIIO_LIB)
	@mkdir -p $(dir $@)
	cp $< $@

fuzz: $(FUZZ_BIN) $(FUZZ_DIR)/libsumi_oiio.so
	@for t in $(FUZZ_TARGETS); do \
	  mkdir -p $(FUZZ_DIR)/corpus_$$t; \
	  case $$t in parse) seeds="$(FUZZ_SEEDS_parse)";; eval) seeds="$(FUZZ_SEEDS_eval)";; \
	    fold) seeds="$(FUZZ_SEEDS_fold)";; mesh) seeds="$(FUZZ_SEEDS_mesh)";; image) seeds="$(FUZZ_SEEDS_image)";; esac; \
	  for f in $$seeds; do [ -f "$$f" ] && cp "$$f" $(FUZZ_DIR)/corpus_$$t/; done; \
	  echo "fuzz $$t: $(FUZZ_SECONDS) s"; \
	  (cd $(FUZZ_DIR) && LSAN_OPTIONS=suppressions=$(CURDIR)/tests/fuzz/lsan.supp ./fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=20 \
	    -rss_limit_mb=3072 -malloc_limit_mb=$(FUZZ_MALLOC_MB) -print_final_stats=1 corpus_$$t) >$(FUZZ_DIR)/fuzz_$$t.log 2>&1 \
	    || { tail -60 $(FUZZ_DIR)/fuzz_$$t.log; exit 1; }; \
	  grep -E "stat::number_of_executed_units|Done" $(FUZZ_DIR)/fuzz_$$t.log | tr '\n' ' '; echo; \
	done

bench-parse: deps all
	sh bench/parse.sh $(BUILD)/sumi

bench-eval: deps all
	sh bench/eval.sh $(BUILD)/sumi

# CSG: the difference of two 100k-triangle meshes, sumi against OpenSCAD's
# own render of the same program (minutes: OpenSCAD's Nef polyhedra).
bench-csg: PEER_PACKAGES := openscad python3 time
bench-csg: deps all
	sh bench/csg.sh $(BUILD)/sumi

# The layer-order solver against Flat-Folder under node (../shared; minutes).
bench-solve: deps all
	sh bench/solve.sh $(BUILD)/sumi

bench: deps all bench-parse bench-eval bench-csg
	sh bench/run.sh $(BUILD)/sumi

# A 7680x4320 frame of the lines scene whole and as 8 tile jobs run 2 at a
# time, plus assemble: CPU time and peak memory (make bench runs it too).
bench-tiles: PEER_PACKAGES := time python3
bench-tiles: deps all
	sh bench/tiles.sh $(BUILD)/sumi

# Large real meshes (issue 24): Wuson and the duck subdivided to level 4,
# the engine as it is, the bench torus; per-stage times, memory, 2 threads;
# CALLGRIND=1 adds each stage's instruction count. The same scenes in
# POV-Ray (a mesh2) and, where blender is installed, Blender with Freestyle
# (not installed here: 300 MB); PEERS=0 leaves them out, PEERS=only runs
# them without sumi's 2-thread and callgrind runs.
bench-bigmesh: PEER_PACKAGES := time python3 assimp-testmodels valgrind povray python3-numpy python3-pil
bench-bigmesh: deps all
	sh bench/bigmesh.sh $(BUILD)/sumi

# An animation of a static mesh (issue 24, item 3): Wuson L4 under an
# orbiting camera, FRAMES frames in one run; each stage at frame 0 and per
# later frame (what the caches across frames leave to do).
bench-orbit: PEER_PACKAGES := time python3 assimp-testmodels
bench-orbit: deps all
	sh bench/orbit.sh $(BUILD)/sumi

# The Slurm recipe (scripts/slurm/) on a one-node cluster this starts on
# localhost: a tile array and its assemble job, and a frame array, against
# single-process renders (tests/slurm.sh; under a minute once installed).
test-slurm: PEER_PACKAGES := slurm-wlm munge python3
test-slurm: deps all
	sh tests/slurm.sh $(BUILD)/sumi

# Every example rendered small under valgrind's memcheck (minutes).
valgrind: PEER_PACKAGES := valgrind
valgrind: deps all
	sh tests/valgrind.sh $(BUILD)/sumi

# Every real crease pattern in ../shared/data/cp against Flat-Folder's
# counts (minutes; make test runs the fast rows).
check-cp: all
	sh tests/cp_check.sh $(BUILD)/sumi

# Every example rendered into docs/gallery/, and docs/gallery/index.html:
# each image, its scene, styles, papers and render time (scripts/gallery.py;
# an example's `// needs: FILE` skips it when FILE is absent, `// frames:
# A:B` makes it an animation, NAME_####.png).
gallery: PEER_PACKAGES := python3
gallery: deps all
	python3 scripts/gallery.py $(BUILD)/sumi examples docs/gallery

# The gallery page in headless Chromium: every image loaded at its size,
# and a screenshot (tests/gallery.sh; build/test-out/gallery/).
test-gallery: PEER_PACKAGES := chromium python3
test-gallery: deps all
	sh tests/gallery.sh $(BUILD)/sumi

PREFIX ?= /usr/local
install: all
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/lib/sumi $(DESTDIR)$(PREFIX)/share/sumi/stdlib
	install -m 755 $(BUILD)/sumi $(DESTDIR)$(PREFIX)/bin/sumi
	install -m 644 $(OIIO_LIB) $(DESTDIR)$(PREFIX)/lib/sumi/
	cp -R stdlib/. $(DESTDIR)$(PREFIX)/share/sumi/stdlib/

clean:
	rm -rf build

help:
	@echo "make            build build/sumi"
	@echo "make deps       install missing Debian packages"
	@echo "make example    deps + build + render examples/teapot_toon.npr"
	@echo "make test       every test suite (SANITIZE=1: under ASan+UBSan)"
	@echo "make update-snapshots / update-golden   rewrite expectations"
	@echo "make fuzz FUZZ_SECONDS=N   libFuzzer: parser, evaluator, FOLD, mesh, image (FUZZ_TARGETS=...)"
	@echo "make test-slurm the Slurm recipe on a one-node cluster started here (installs slurm-wlm, munge)"
	@echo "make bench / bench-parse / bench-eval   benchmarks with peers"
	@echo "make bench-solve the layer solver against Flat-Folder (node)"
	@echo "make bench-csg   difference of two 100k-triangle meshes against OpenSCAD (CPU)"
	@echo "make bench-tiles a 7680x4320 frame whole and as 8 tile jobs (CPU, memory)"
	@echo "make bench-bigmesh  level-4 Wuson, duck, engine, torus: per-stage times, memory; POV-Ray, Blender"
	@echo "make bench-orbit    Wuson L4 orbit under --frames: each stage at frame 0 and per later frame"
	@echo "make valgrind   every example rendered small under valgrind (memory errors, leaks)"
	@echo "make check-cp   the layer solver on every real crease pattern (../shared)"
	@echo "make gallery    render every example into docs/gallery/ and write its index.html"
	@echo "make test-gallery  the gallery page in headless Chromium (installs chromium)"

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
