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
OPT   := -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined
endif

VERSION  := $(shell cat VERSION)
CPPFLAGS += -Iinclude -Isrc -I/usr/include/OpenEXR -D_DEFAULT_SOURCE -MMD -MP
CFLAGS   += -std=c11 $(OPT) -Wall -Wextra -fopenmp -march=x86-64-v2
CXXFLAGS += -std=c++17 $(OPT) -Wall -Wextra -I/usr/include/opencv4
LDFLAGS  += $(OPT) -fopenmp
LDLIBS   := -lopencv_calib3d -lopencv_imgcodecs -lopencv_imgproc -lopencv_core \
            -lOpenEXRCore-3_1 -lproj -llapacke -llapack -lblas -lstdc++ -lm

LIB_C    := $(wildcard src/*/*.c)
LIB_CXX  := $(wildcard src/*/*.cpp)
TEST_SRC := $(wildcard tests/unit/*/test_*.c)
LIB_OBJ  := $(LIB_C:src/%.c=$(BUILD)/src/%.o) $(LIB_CXX:src/%.cpp=$(BUILD)/src/%.o)
CMDS     := $(patsubst cmd/%.c,$(BIN)/%,$(wildcard cmd/lens-*.c))
TESTS    := $(patsubst %.c,$(BUILD)/tests/%,$(notdir $(TEST_SRC)))
BENCHES  := $(patsubst bench/%.c,$(BUILD)/bench/%,$(wildcard bench/bench_*.c))
LIB      := $(BUILD)/liblens.a

.PHONY: all deps test check demo bench reports install fuzz clean
all: $(CMDS) $(TESTS) $(BENCHES)

deps:
	@tools/install-deps.sh

# Header dependencies come from the compiler (-MMD -MP: a .d file beside each object);
# the flags live here, so a changed Makefile rebuilds the objects too.
$(LIB_OBJ): Makefile

$(BUILD)/src/%.o: src/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/src/%.o: src/%.cpp
	@mkdir -p $(dir $@)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -c $< -o $@

$(LIB): $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

# The version (one place: the VERSION file) reaches the commands through options.c.
$(BUILD)/src/app/options.o: CPPFLAGS += -DSPARSELENS_VERSION='"$(VERSION)"'
$(BUILD)/src/app/options.o: VERSION

$(BIN)/lens-%: cmd/lens-%.c $(LIB)
	@mkdir -p $(BIN) $(BUILD)/cmd
	$(CC) $(CPPFLAGS) -MF $(BUILD)/cmd/lens-$*.d -MT $@ $(CFLAGS) $< $(LIB) $(LDFLAGS) $(LDLIBS) -o $@

vpath test_%.c $(sort $(dir $(TEST_SRC)))
$(BUILD)/tests/test_%: test_%.c $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) -MF $@.d -MT $@ -Itests/unit $(CFLAGS) $< $(LIB) $(LDFLAGS) -lcmocka $(LDLIBS) -o $@

$(BUILD)/bench/%: bench/%.c $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) -MF $@.d -MT $@ $(CFLAGS) -O3 $< $(LIB) $(LDFLAGS) $(LDLIBS) -o $@

-include $(LIB_OBJ:.o=.d) $(patsubst $(BIN)/%,$(BUILD)/cmd/%.d,$(CMDS)) $(TESTS:=.d) $(BENCHES:=.d)

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

reports: deps
	@$(MAKE) --no-print-directory -j$(shell nproc 2>/dev/null || echo 2) all
	@$(MAKE) --no-print-directory -f tools/reports.mk BIN=$(BIN) BUILD=$(BUILD)

fuzz: deps
	@tools/fuzz.sh $(or $(FUZZ_SECONDS),60)

install: all
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/share/man/man1 \
	           $(DESTDIR)$(PREFIX)/share/man/man5 $(DESTDIR)$(PREFIX)/share/sparselens/lenses
	install -m 755 $(CMDS) $(DESTDIR)$(PREFIX)/bin
	install -m 644 $(wildcard man/*.1) $(DESTDIR)$(PREFIX)/share/man/man1
	install -m 644 $(wildcard man/*.5) $(DESTDIR)$(PREFIX)/share/man/man5
	install -m 644 $(wildcard lenses/*) $(DESTDIR)$(PREFIX)/share/sparselens/lenses

clean:
	rm -rf build build-san bin bin-san
