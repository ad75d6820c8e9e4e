# Raster101 — a thin front door over CMake. The two commands a new user needs:
#   make demo   installs what is missing, builds, renders every assignment's
#               default scene with the reference solutions into out/
#   make test   installs what is missing, builds, runs the self-test suite
BUILD ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
# Tests at once: one more than JOBS (the cores). The long tests (the gradings, the
# packages' setups, the GUI under Xvfb, the sandbox's wall clocks) wait part
# of their time, so at one test a core the cores sat idle: on this project's
# 2-core machine the suite took 240 s at -j 2, 189 s at -j 3, 188 s at -j 4
# (built, quiet, 2026-12-06).
TEST_JOBS ?= $(shell echo $$(( $(JOBS) + 1 )))
CMAKE_FLAGS ?=
# CI builds treat warnings as errors.
ifeq ($(CI),true)
CMAKE_FLAGS += -DRAS_WERROR=ON
endif

.PHONY: all deps configure build demo test clean reference-images format

all: build

deps:
	@scripts/install-deps

configure: deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS) -- --no-print-directory

demo: build
	@scripts/demo $(BUILD)

# Everything but the student variants, which fail by design until written
# (grade those with `make grade`). ctest runs in the build folder, which every
# CMake understands (`ctest --test-dir` is 3.20: 3.18 ignores it and finds no
# test); --no-tests=error (3.17) makes a run that finds no test fail.
# (glibc's malloc asks for transparent huge pages, as the grader's processes
# do: tests/grading/grade says why; the tests compute the same bytes)
test: build
	@cd $(BUILD) && GLIBC_TUNABLES=$${GLIBC_TUNABLES:+$$GLIBC_TUNABLES:}glibc.malloc.hugetlb=1 \
	  ctest --no-tests=error --output-on-failure -j $(TEST_JOBS) -LE student

reference-images: build
	@scripts/reference-images $(BUILD)

format:
	@clang-format -i common/*/*.[ch] common/*/*.cpp fast/*.[ch] hw*/*.[ch] hw*/solution/*.c \
	  tests/unit/*.[ch] tests/grading/*.[ch] tests/bench/*.[ch]

clean:
	rm -rf $(BUILD) out

# ---- grading (tests/grading/grade, docs/grading.md) ----
#   make grade              builds the student programs in build/bin, grades the student code
#   make grade HW=2         one assignment
#   make grade STUDENT=ref  grades the reference solutions as the student (full marks)
.PHONY: grade
# (the student programs are built in the grader's one make of the trusted
# side, --programs: those of hwN's images with HW=N, every assignment's
# without; an image's program is named after its assignment, hwN_...)
grade: $(BUILD)/CMakeFiles/cmake.check_cache
	@tests/grading/grade --build $(BUILD) --jobs $(JOBS) --reuse-build $(BUILD)/grade-sandbox \
	  --programs "$(GRADE_PROGRAMS)" $(if $(HW),--hw $(HW)) $(if $(STUDENT),--student $(STUDENT))
RUBRIC_PROGRAMS = $(sort $(shell sed -n 's/.*"program": *"\([^"]*\)".*/\1/p' tests/grading/rubric.json))
GRADE_PROGRAMS = $(if $(HW),$(filter hw$(patsubst hw%,%,$(HW))_%,$(RUBRIC_PROGRAMS)),$(RUBRIC_PROGRAMS))

# A build folder is configured once: the grading loop (make grade) does not
# ask dpkg about every package nor re-run cmake's configure at each edit;
# `cmake --build` re-runs the configure itself when a CMakeLists.txt changed,
# and `make configure` still forces both.
$(BUILD)/CMakeFiles/cmake.check_cache:
	@scripts/install-deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) >/dev/null

# The student edition: build/handout/raster101-handout.tar.gz, no solution/
# folders; fails if any solution text would ship (tests/grading/make-handout).
.PHONY: handout
handout:
	@tests/grading/make-handout --out $(BUILD)/handout

# The Gradescope autograder: build/autograder/raster101-autograder.zip
# (setup.sh, run_autograder and the tree without solutions; tests/grading/make-autograder,
# docs/instructors.md). The same zip serves a GitHub Actions runner.
.PHONY: autograder
autograder:
	@tests/grading/make-autograder --out $(BUILD)/autograder

# The PrairieLearn package: build/prairielearn/ in PrairieLearn's course layout
# (questions/hwN with external grading, serverFilesCourse/raster101 with the
# grader and its entrypoint pl-grade, the grading image's Dockerfile;
# tests/grading/make-prairielearn, docs/instructors.md "PrairieLearn").
.PHONY: prairielearn
prairielearn:
	@tests/grading/make-prairielearn --out $(BUILD)/prairielearn

# The accuracy report: time and error of every accuracy option,
# measured on this machine, into docs/accuracy.md, docs/accuracy.csv and
# docs/img/accuracy_*.png. A few minutes; `bench_accuracy --quick` for seconds.
.PHONY: bench-accuracy
bench-accuracy: configure
	@cmake --build $(BUILD) -j $(JOBS) --target bench_accuracy
	@$(BUILD)/bin/bench_accuracy --out docs

# The tests are tested and the grades fair: the classic solution gets full
# marks; known student mistakes (tests/grading/mutants/) injected into the reference
# each lose points in their own assignment first and are named first
# (docs/mutants.md; 15-30 minutes, tests/grading/run-mutants --own-only is faster).
.PHONY: mutants
mutants: configure
	@tests/grading/run-mutants --build $(BUILD)

# The grader is tested against cheating: every hostile submission of
# tests/grading/attacks/ must score 0 on what it attacks, leave no process and no file
# changed, and not change honest students' grades in a mixed grade-all batch
# (tests/grading/run-attacks, docs/grader.md "The attack catalogue"; instructors' only).
.PHONY: attacks
attacks: configure
	@tests/grading/run-attacks --build $(BUILD)

# The performance report: frame times of the classic hw3 scene, the teaching
# pipeline vs the fast renderer (fast/), into docs/performance.md.
# SPOT=DIR uses DIR/spot_triangulated_good.obj (else a built-in teapot).
.PHONY: bench-perf
# Beside them Mesa llvmpipe (tests/bench/bench_llvmpipe.c, OSMesa installed by
# scripts/install-bench-deps), and the rows as CSV into docs/performance.csv.
# INSTRUCTIONS=1 also counts one frame's instructions with callgrind (minutes).
bench-perf: BUILD = build-perf
bench-perf:
	@scripts/install-bench-deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release >/dev/null
	@cmake --build $(BUILD) -j $(JOBS) --target bench_perf bench_llvmpipe hw3_shading_ref -- --no-print-directory
	@$(BUILD)/bin/bench_perf $(if $(SPOT),--spot $(SPOT)) --out docs/performance.md \
	  --csv docs/performance.csv $(if $(INSTRUCTIONS),--instructions)

# How long a student waits for a verdict: the first `make test` in a fresh
# handout, edit → `make grade HW=n`, edit → the student's `ctest -L hwN`, a whole
# `make grade` and one class-graded submission, RUNS rounds alternating, with the
# load average, into docs/feedback.md and docs/feedback.csv (tests/bench/bench-feedback;
# several minutes a round).
.PHONY: bench-feedback
bench-feedback:
	@tests/bench/bench-feedback $(if $(RUNS),--runs $(RUNS))

# The pictures and grader messages of docs/pitfalls.md (+ docs/zh/), made from
# the mutants (scripts/pitfall-gallery; about 20 s a mistake).
.PHONY: pitfall-gallery
pitfall-gallery: build
	@scripts/pitfall-gallery $(BUILD)
