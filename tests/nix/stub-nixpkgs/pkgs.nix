# The package set flake.nix uses, one system. Derivations here are only
# instantiated (`nix flake check --no-build`), never built: the builder
# would just fail.
{ lib, system }:
let
  stubDerivation = attrs:
    derivation ({ inherit system; builder = "/bin/sh"; args = [ "-c" "exit 1" ]; } // attrs);

  package = name: stubDerivation { inherit name; };

  # Like stdenv.mkDerivation: `env` becomes environment variables, `meta` and
  # `passthru` are attributes of the result, not of the derivation.
  mkDerivation = args:
    stubDerivation (builtins.removeAttrs args [ "env" "meta" "passthru" ] // (args.env or { }) // {
      name = args.name or "${args.pname}-${args.version}";
    }) // { meta = args.meta or { }; } // (args.passthru or { });

  mkShellWith = { stdenv }: args:
    stdenv.mkDerivation ({ name = "nix-shell"; } // args);

  gcc14Stdenv = { mkDerivation = mkDerivation; };

  pythonPackageNames = [ "pandas" "numpy" "matplotlib" "scipy" "rich" "pytest" "pytest-xdist" ];
  pythonPackages = lib.genAttrs pythonPackageNames (name: package "python3.13-${name}");
in
lib.genAttrs [
  "bash"
  "cmake"
  "ninja"
  "pkg-config"
  "glslang"
  "makeWrapper"
  "glm"
  "nlohmann_json"
  "simdjson"
  "cli11"
  "stb"
  "onetbb"
  "libhwy"
  "gtest"
  "vulkan-headers"
  "vulkan-loader"
  "vulkan-tools"
  "vulkan-validation-layers"
  "mesa"
  "ruff"
  "git"
  "glfw"
  "embree"
  "iproute2"
  "imagemagick"
] package // {
  inherit gcc14Stdenv;

  # An LLVM release is a set of its own (clang-format is in clang-tools).
  llvmPackages_19 = { clang-tools = package "clang-tools-19"; };

  # X.Org packages are a set of their own (Xvfb is in xorgserver).
  xorg = lib.genAttrs [ "xorgserver" "xwininfo" "xwd" "libX11" "libXtst" ] package;

  # Tracy's sources are an attribute of the package (fetchFromGitHub).
  tracy = package "tracy-0.11.1" // { src = package "source"; };

  python3 = package "python3-3.13" // {
    withPackages = select: stubDerivation {
      name = "python3-3.13-env";
      packages = select pythonPackages;
    };
  };

  # mkShell is callPackage'd in nixpkgs: it can be called and overridden.
  mkShell = {
    __functor = _: mkShellWith { stdenv = gcc14Stdenv; };
    override = mkShellWith;
  };

  runCommand = name: env: buildCommand: stubDerivation (env // { inherit name buildCommand; });

  # Keeps its arguments as attributes so that the test can read them back.
  writeShellApplication = { name, text, runtimeInputs ? [ ], runtimeEnv ? { } }:
    stubDerivation { inherit name text runtimeInputs; } // {
      inherit runtimeEnv;
      meta.mainProgram = name;
    };
}
