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
	./target/release/translucid render $(DEMO_SCENE) --method $(DEMO_METHOD) --size $(DEMO_SIZE) -o out/demo.png

lint: deps
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets -- -D warnings

test: deps lint
	$(CARGO) test --workspace

# Not part of `test`: runs the glTF import fuzzer for FUZZ_SECONDS (see README, "Fuzzing").
fuzz: deps
	$(CARGO) run --release -p translucid-fuzz -- gltf --seconds $(FUZZ_SECONDS)
