# sparselens: `make` builds bin/ and build/; see README.md for the other targets.
# Sources are discovered by wildcard so that adding a file never needs an edit here:
#   src/<stage>/*.c, src/<stage>/*.cpp -> build/liblens.a (public headers: include/sparselens/)
#   cmd/lens-<verb>.c                  -> bin/lens-<verb>
#   tests/unit/<stage>/test_*.c        -> build/tests/test_* (cmocka)
#   bench/bench_*.c     -> build/bench/bench_* (`make bench` runs tools/bench.sh)
#   tests/fuzz/fuzz_*.c -> build-fuzz/fuzz_* (libFuzzer, clang; `make fuzz`)

PREFIX   ?= /usr/local
SANITIZE ?=
CC       ?= cc
CXX      ?= c++

ifeq ($(SANITIZE),)
BUILD := build
BIN   := bin
OPT   := -O2 -g
else
BUILD := build-san
BIN   := bin-san
# float-cast-overflow explicitly: GCC's -fsanitize=undefined leaves it out (clang's has it),
# and a double too large for a long is undefined behaviour (a tiny checker square did it).
SAN_FLAGS := -fsanitize=address,undefined,float-cast-overflow
OPT   := -O1 -g -fno-omit-frame-pointer $(SAN_FLAGS) \
         -fno-sanitize-recover=undefined,float-cast-overflow
endif

VERSION  := $(shell cat VERSION)
# Header dependencies come from the compiler: a .d file beside each output.
DEPFLAGS := -MMD -MP
# Libraries are found by pkg-config; where a distribution ships no .pc file (Debian's
# split OpenCV packages have no opencv4.pc, OpenEXR 3 has no OpenEXRCore.pc) the
# compiler is asked where the header lies and the library is named plainly. Only the
# OpenCV modules and the OpenEXR Core library the code uses are linked.
# `make print-VAR` prints a variable (tests and tools that build on their own use it).
PKG_CONFIG ?= pkg-config
pkg       = $(shell $(PKG_CONFIG) $(1) 2>/dev/null || echo '$(2)')
# $(call header_dir,LANG,HEADER,SUFFIX): the include directory the compiler finds
# HEADER in, without SUFFIX (e.g. opencv4/opencv2/core.hpp -> .../include/opencv4).
header_dir = $(patsubst %/$(3),%,$(firstword $(filter %/$(3),$(shell printf '\043include <%s>\n' '$(2)' | \
             $(if $(filter c++,$(1)),$(CXX) -x c++,$(CC) -x c) -M -MG - 2>/dev/null))))
OPENCV_CFLAGS := $(call pkg,--cflags opencv4,$(addprefix -I,$(call header_dir,c++,opencv4/opencv2/core.hpp,opencv2/core.hpp)))
OPENCV_LIBS   := $(call pkg,--libs-only-L opencv4,) -lopencv_calib3d -lopencv_imgcodecs -lopencv_imgproc -lopencv_core
EXR_CFLAGS    := $(call pkg,--cflags OpenEXRCore,$(call pkg,--cflags OpenEXR,$(addprefix -I,$(call header_dir,c,OpenEXR/openexr.h,openexr.h))))
EXR_LIBS      := $(call pkg,--libs OpenEXRCore,$(or $(filter -L% -lOpenEXRCore%,$(call pkg,--libs OpenEXR,)),-lOpenEXRCore))
PROJ_CFLAGS   := $(call pkg,--cflags proj,)
PROJ_LIBS     := $(call pkg,--libs proj,-lproj)
LAPACK_CFLAGS := $(call pkg,--cflags lapacke,)
LAPACK_LIBS   := $(call pkg,--libs lapacke,-llapacke) $(call pkg,--libs lapack,-llapack) $(call pkg,--libs blas,-lblas)
CAIRO_CFLAGS  := $(call pkg,--cflags cairo,$(addprefix -I,$(call header_dir,c,cairo/cairo.h,cairo.h)))
CAIRO_LIBS    := $(call pkg,--libs cairo,-lcairo)
# Number text (src/base/numtext.cpp): double-conversion's digits, fast_float's parser
# (header-only).
DCONV_LIBS    := $(call pkg,--libs double-conversion,-ldouble-conversion)
CMOCKA_CFLAGS := $(call pkg,--cflags cmocka,)
CMOCKA_LIBS   := $(call pkg,--libs cmocka,-lcmocka)
# x86-64-v2 (SSE4.2, POPCNT) is the baseline on x86-64, where the poly and trace kernels
# also carry AVX2/AVX-512 clones chosen at run time; elsewhere (arm64, ...) the compiler's
# default target and the kernels' portable path.
MACHINE  := $(shell $(CC) -dumpmachine 2>/dev/null)
ARCH_FLAGS ?= $(if $(filter x86_64-%,$(MACHINE)),-march=x86-64-v2,)

CPPFLAGS += -Iinclude -Isrc $(EXR_CFLAGS) $(PROJ_CFLAGS) $(LAPACK_CFLAGS) -D_DEFAULT_SOURCE
CFLAGS   += -std=c11 $(OPT) -Wall -Wextra -fopenmp $(ARCH_FLAGS)
CXXFLAGS += -std=c++17 $(OPT) -Wall -Wextra $(OPENCV_CFLAGS)
LDFLAGS  += $(OPT) -fopenmp
LDLIBS   := $(OPENCV_LIBS) $(DCONV_LIBS) $(CAIRO_LIBS) $(EXR_LIBS) $(PROJ_LIBS) $(LAPACK_LIBS) -lstdc++ -lm

LIB_C    := $(wildcard src/*/*.c)
LIB_CXX  := $(wildcard src/*/*.cpp)
TEST_SRC := $(wildcard tests/unit/*/test_*.c)
LIB_OBJ  := $(LIB_C:src/%.c=$(BUILD)/src/%.o) $(LIB_CXX:src/%.cpp=$(BUILD)/src/%.o)
CMDS     := $(patsubst cmd/%.c,$(BIN)/%,$(wildcard cmd/lens-*.c))
TESTS    := $(patsubst %.c,$(BUILD)/tests/%,$(notdir $(TEST_SRC)))
BENCHES  := $(patsubst bench/%.c,$(BUILD)/bench/%,$(wildcard bench/bench_*.c))
LIB      := $(BUILD)/liblens.a

.PHONY: all deps test check demo bench bench-compare reports realworld figures install fuzz clean man
all: $(CMDS) $(TESTS) $(BENCHES) man

# The SYNOPSIS and OPTIONS sections of each command's man page are generated from its
# option table (lens-x --help-man, spliced in by tools/man-options.sh): rebuilt with the
# command.
MAN_STAMPS := $(patsubst $(BIN)/%,$(BUILD)/man/%.stamp,$(CMDS))
man: $(MAN_STAMPS)
$(BUILD)/man/%.stamp: $(BIN)/% man/%.1 tools/man-options.sh
	@mkdir -p $(dir $@)
	tools/man-options.sh man/$*.1 $(BIN)/$*
	@touch $@

deps:
	@tools/install-deps.sh

# Header dependencies come from the .d files (DEPFLAGS); the flags live here, so a
# changed Makefile rebuilds the objects too.
$(LIB_OBJ): Makefile

$(BUILD)/src/%.o: src/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(DEPFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/src/%.o: src/%.cpp
	@mkdir -p $(dir $@)
	$(CXX) $(CPPFLAGS) $(DEPFLAGS) $(CXXFLAGS) -c $< -o $@

# The library objects are position-independent: one object set makes both the archive
# the commands link and the installed libsparselens.so (`make bench` shows the kernels
# no slower for it: their hot loops are within one file; README, "Using the library").
$(LIB_OBJ): CFLAGS += -fPIC
$(LIB_OBJ): CXXFLAGS += -fPIC

$(LIB): $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

# The version (one place: the VERSION file) reaches the commands through options.c.
$(BUILD)/src/base/canvas_cairo.o: CPPFLAGS += $(CAIRO_CFLAGS)
$(BUILD)/src/app/options.o: CPPFLAGS += -DSPARSELENS_VERSION='"$(VERSION)"'
$(BUILD)/src/app/options.o: VERSION

$(BIN)/lens-%: cmd/lens-%.c $(LIB)
	@mkdir -p $(BIN) $(BUILD)/deps
	$(CC) $(CPPFLAGS) $(DEPFLAGS) -MF $(BUILD)/deps/lens-$*.d -MT $@ $(CFLAGS) $< $(LIB) $(LDFLAGS) $(LDLIBS) -o $@

vpath test_%.c $(sort $(dir $(TEST_SRC)))
$(BUILD)/tests/test_%: test_%.c $(LIB)
	@mkdir -p $(dir $@) $(BUILD)/deps
	$(CC) $(CPPFLAGS) $(DEPFLAGS) -MF $(BUILD)/deps/$(notdir $@).d -MT $@ $(CMOCKA_CFLAGS) -Itests/unit $(CFLAGS) $< $(LIB) $(LDFLAGS) $(CMOCKA_LIBS) $(LDLIBS) -o $@

$(BUILD)/bench/%: bench/%.c $(LIB)
	@mkdir -p $(dir $@) $(BUILD)/deps
	$(CC) $(CPPFLAGS) $(DEPFLAGS) -MF $(BUILD)/deps/$(notdir $@).d -MT $@ $(CFLAGS) -O3 $< $(LIB) $(LDFLAGS) $(LDLIBS) -o $@

-include $(LIB_OBJ:.o=.d) $(wildcard $(BUILD)/deps/*.d)

# The whole suite: unit tests, command-line tests, hard cases, short fuzz runs.
test: deps
	@$(MAKE) --no-print-directory -j$(shell nproc 2>/dev/null || echo 2) all
	@BIN=$(BIN) BUILD=$(BUILD) SANITIZE=$(SANITIZE) tests/run-tests.sh

check: test

# The whole pipeline on the default lens; results in demo/.
demo: deps
	@$(MAKE) --no-print-directory -j$(shell nproc 2>/dev/null || echo 2) all
	@BIN=$(BIN) tools/demo.sh

bench: deps
	@$(MAKE) --no-print-directory -j$(shell nproc 2>/dev/null || echo 2) all
	@BIN=$(BIN) tools/bench.sh

# Two revisions' kernels side by side (tools/bench-compare.sh): make bench-compare A=REV
# B=REV [RUNS=5] [RAYS=20000]; "." is the working tree (the default B, with A=HEAD).
bench-compare: deps
	@$(MAKE) --no-print-directory -j$(shell nproc 2>/dev/null || echo 2) all
	@BIN=$(BIN) BUILD=$(BUILD) tools/bench-compare.sh $(or $(A),HEAD) $(or $(B),.) $(or $(RUNS),5) $(or $(RAYS),20000)

reports: deps
	@$(MAKE) --no-print-directory -j$(shell nproc 2>/dev/null || echo 2) all
	@$(MAKE) --no-print-directory -f tools/reports.mk BIN=$(BIN) BUILD=$(BUILD)

# The pipeline on the public prescriptions of lenses/realworld (files nobody here wrote):
# reports/realworld.md (tools/realworld.sh; about 3 min on 2 cores).
realworld: deps
	@$(MAKE) --no-print-directory -j$(shell nproc 2>/dev/null || echo 2) all
	@BIN=$(BIN) tools/realworld.sh $(BUILD)/realworld

# The accuracy report and its pictures from the committed sweeps (reports/cache), no sweep.
figures:
	@python3 tools/report_accuracy.py reports/cache reports/accuracy-vs-time.md reports/accuracy
	@echo "figures: wrote reports/accuracy-vs-time.md and reports/accuracy/" >&2

fuzz: deps
	@tools/fuzz.sh $(or $(FUZZ_SECONDS),60)

# make install [PREFIX=/usr/local] [DESTDIR=]: the library (below), the commands, linked again with
# PREFIX/share/sparselens compiled in as the data directory (data_path.h; the commands
# also find it beside themselves, so a DESTDIR copy works before it is moved), the man
# pages (source-tree paths in their text turned into installed ones), and the lenses
# (with the reference prescriptions) and scenes under PREFIX/share/sparselens, so that
# `lens-info dgauss.50mm` and `lens-render dgauss` work from any directory.
DATADIR   = $(PREFIX)/share/sparselens
MANDIR    = $(PREFIX)/share/man
INST     := $(BUILD)/install
INST_CMDS := $(patsubst cmd/%.c,$(INST)/bin/%,$(wildcard cmd/lens-*.c))
MANPAGES := $(wildcard man/*.[1-8])
.PHONY: FORCE
$(INST)/datadir.txt: FORCE
	@mkdir -p $(dir $@)
	@echo '$(DATADIR)' | cmp -s - $@ || echo '$(DATADIR)' > $@

$(INST)/data_path.o: src/base/data_path.c include/sparselens/data_path.h $(INST)/datadir.txt
	$(CC) $(CPPFLAGS) -DSPARSELENS_DATADIR='"$(DATADIR)"' $(CFLAGS) -fPIC -c $< -o $@

# The library (man 3 sparselens): libsparselens.so.VERSION with the soname
# libsparselens.so.MAJOR, exporting exactly what the public headers declare (the
# umbrella include/sparselens.h and the headers it includes, the only ones installed:
# tools/public-symbols.sh makes the version script), libsparselens.a, and sparselens.pc
# (Libs.private: what a static link needs; a sanitized build's Libs carries the sanitizers,
# whose runtime must come first in a program that loads it). Both hold the installed data
# directory.
LIBDIR    = $(PREFIX)/lib
INCDIR    = $(PREFIX)/include
MAJOR    := $(firstword $(subst ., ,$(VERSION)))
SONAME   := libsparselens.so.$(MAJOR)
PUBLIC_HEADERS := $(shell sed -n 's,^\#include "\(sparselens/.*\.h\)",include/\1,p' include/sparselens.h)
INST_LIB_OBJ := $(filter-out $(BUILD)/src/base/data_path.o,$(LIB_OBJ)) $(INST)/data_path.o
INST_LIBS := $(INST)/libsparselens.so.$(VERSION) $(INST)/libsparselens.a $(INST)/sparselens.pc

$(INST)/libsparselens.map: include/sparselens.h $(PUBLIC_HEADERS) tools/public-symbols.sh
	@mkdir -p $(dir $@)
	{ echo 'SPARSELENS_$(MAJOR) {'; echo 'global:'; \
	  tools/public-symbols.sh '$(CC)' include/sparselens.h | sed 's/.*/  &;/'; \
	  echo 'local: *;'; echo '};'; } > $@.tmp && mv $@.tmp $@

$(INST)/libsparselens.so.$(VERSION): $(INST_LIB_OBJ) $(INST)/libsparselens.map
	$(CC) -shared -Wl,-soname,$(SONAME) -Wl,--version-script=$(INST)/libsparselens.map \
	  -Wl,--no-undefined $(INST_LIB_OBJ) $(LDFLAGS) $(LDLIBS) -o $@

$(INST)/libsparselens.a: $(INST_LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(INST)/sparselens.pc: Makefile VERSION $(INST)/datadir.txt
	printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$(LIBDIR)' 'includedir=$(INCDIR)' '' \
	  'Name: sparselens' \
	  'Description: lens prescriptions, exact ray tracing, sparse polynomial optics and a lens camera' \
	  'Version: $(VERSION)' 'Cflags: -I$${includedir}' 'Libs: -L$${libdir} -lsparselens $(SAN_FLAGS)' \
	  'Libs.private: $(strip $(LDLIBS)) -lgomp' > $@

$(INST)/bin/lens-%: cmd/lens-%.c $(INST)/data_path.o $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) $< $(INST)/data_path.o $(LIB) $(LDFLAGS) $(LDLIBS) -o $@

install: $(INST_CMDS) $(INST_LIBS) man
	install -d $(DESTDIR)$(LIBDIR)/pkgconfig $(DESTDIR)$(INCDIR)/sparselens
	install -m 755 $(INST)/libsparselens.so.$(VERSION) $(DESTDIR)$(LIBDIR)
	ln -sf libsparselens.so.$(VERSION) $(DESTDIR)$(LIBDIR)/$(SONAME)
	ln -sf $(SONAME) $(DESTDIR)$(LIBDIR)/libsparselens.so
	install -m 644 $(INST)/libsparselens.a $(DESTDIR)$(LIBDIR)
	install -m 644 $(INST)/sparselens.pc $(DESTDIR)$(LIBDIR)/pkgconfig
	install -m 644 include/sparselens.h $(DESTDIR)$(INCDIR)
	install -m 644 $(PUBLIC_HEADERS) $(DESTDIR)$(INCDIR)/sparselens
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(DATADIR)/lenses/reference/fx \
	           $(DESTDIR)$(DATADIR)/lenses/reference/pbrt $(DESTDIR)$(DATADIR)/scenes \
	           $(addprefix $(DESTDIR)$(MANDIR)/man,$(sort $(subst .,,$(suffix $(MANPAGES)))))
	install -m 755 $(INST_CMDS) $(DESTDIR)$(PREFIX)/bin
	for m in $(MANPAGES); do \
	  sed -e 's#\(^\|[ (]\)\(lenses\|scenes\)/#\1$(DATADIR)/\2/#g' $$m > $(DESTDIR)$(MANDIR)/man$${m##*.}/$${m##*/} && \
	  chmod 644 $(DESTDIR)$(MANDIR)/man$${m##*.}/$${m##*/} || exit 1; done
	install -m 644 $(filter-out %.md,$(wildcard lenses/*.*)) $(DESTDIR)$(DATADIR)/lenses
	install -m 644 lenses/reference/README.md $(DESTDIR)$(DATADIR)/lenses/reference
	install -m 644 $(wildcard lenses/reference/fx/*) $(DESTDIR)$(DATADIR)/lenses/reference/fx
	install -m 644 $(wildcard lenses/reference/pbrt/*) $(DESTDIR)$(DATADIR)/lenses/reference/pbrt
	install -m 644 $(wildcard scenes/*) $(DESTDIR)$(DATADIR)/scenes

clean:
	rm -rf build build-san bin bin-san

print-%:
	@echo '$($*)'
