# translucid: `make demo` renders a real scene, `make test` runs every test.
# Both install what they need first (Debian packages, see scripts/install-deps.sh).

CARGO ?= cargo
DEMO_SCENE ?= assets/scenes/GlassVaseFlowers/GlassVaseFlowers.glb
DEMO_SIZE ?= 1280x720
DEMO_METHOD ?= exact
FUZZ_SECONDS ?= 60

.PHONY: all deps demo test lint fuzz

all: demo

deps:
	@./scripts/install-deps.sh

demo: deps
	$(CARGO) build --release -p translucid-cli
	./target/release/translucid render $(DEMO_SCENE) --method $(DEMO_METHOD) --size $(DEMO_SIZE) -o out/demo.png --warm

lint: deps
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets -- -D warnings

# Lavapipe 22.3 keys its shader cache without its vector width, so a process at one
# LP_NATIVE_VECTOR_WIDTH can load code compiled at another and corrupt its memory
# (docs/gpu.md): the suite keeps a cache of its own for the width it runs at.
test: deps lint
	MESA_SHADER_CACHE_DIR=$(CURDIR)/target/mesa-shader-cache-$${LP_NATIVE_VECTOR_WIDTH:-256} \
		$(CARGO) test --workspace

# Runs the glTF import fuzzer, then the C API fuzzer, for FUZZ_SECONDS each (README,
# "Fuzzing"). `make test` runs both on fixed cases instead.
CAPI_FUZZER = target/fuzz/fuzz_calls
FUZZ_SEED ?= $(shell date +%s)
# More arguments for the C API fuzzer: `--threads N` (cases on N threads at once, each on
# contexts of its own), `--host-device` (contexts on an engine's device).
FUZZ_CAPI_ARGS ?=

fuzz: deps
	$(CARGO) run --release -p translucid-fuzz -- gltf --seconds $(FUZZ_SECONDS) --seed $(FUZZ_SEED)
	$(CARGO) build --release -p translucid-ffi
	mkdir -p target/fuzz
	cc -std=c11 -pthread -g -O1 -fsanitize=address,undefined -fno-sanitize-recover=all \
		-fno-omit-frame-pointer -Iinclude -Iexamples-c crates/translucid-ffi/tests/c/fuzz_calls.c \
		crates/translucid-ffi/tests/c/fuzz_host.c examples-c/engine.c \
		crates/translucid-ffi/tests/c/checks.c crates/translucid-ffi/tests/c/keep_modules.c \
		-o $(CAPI_FUZZER) \
		-Ltarget/release -ltranslucid_ffi -Wl,-rpath,$(CURDIR)/target/release -lm -lvulkan
	TRANSLUCID_VALIDATION=1 ASAN_OPTIONS=detect_leaks=1 \
		$(CAPI_FUZZER) --seconds $(FUZZ_SECONDS) --seed $(FUZZ_SEED) $(FUZZ_CAPI_ARGS)
