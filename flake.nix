{
  description = "raytracer: the reproducibility kit for parallel ray tracing, with a pinned toolchain and Mesa's lavapipe";

  # nixos-25.11 as of 2026-05-10, pinned by revision: the revision alone fixes
  # nixpkgs (GCC 14.3, Mesa 25.2, Tracy 0.11.1, Python 3.13, ...).
  inputs.nixpkgs.url = "github:NixOS/nixpkgs/8fd9daa3db09ced9700431c5b7ad0e8ba199b575";

  outputs = { self, nixpkgs }:
    let
      inherit (nixpkgs) lib;
      systems = [ "x86_64-linux" "aarch64-linux" ];
      forAllSystems = f: lib.genAttrs systems (system: f system nixpkgs.legacyPackages.${system});

      # Mesa names lavapipe's ICD file after the CPU.
      icdArch = { x86_64-linux = "x86_64"; aarch64-linux = "aarch64"; };

      # Recorded in every run's metadata (build.nix, src/app/run_metadata.cpp).
      nixEnv = { RT_NIX = "1"; RT_NIXPKGS_REV = nixpkgs.rev or "unknown"; };

      # The store copy of the sources has no .git; cmake/BuildInfo.cmake takes
      # the commit from the environment instead (build.git_commit / git_dirty).
      gitEnv =
        if self ? rev then { RT_GIT_COMMIT = self.rev; RT_GIT_DIRTY = "false"; }
        else if self ? dirtyRev then { RT_GIT_COMMIT = builtins.substring 0 40 self.dirtyRev; RT_GIT_DIRTY = "true"; }
        else { };

      # One place for the version: project(raytracer VERSION x.y.z) in CMakeLists.txt.
      version =
        let
          lines = builtins.filter builtins.isString (builtins.split "\n" (builtins.readFile ./CMakeLists.txt));
          matches = builtins.concatMap
            (line: let m = builtins.match "project\\(raytracer VERSION ([0-9.]+).*" line; in if m == null then [ ] else m)
            lines;
        in
        builtins.head matches;

      # The project's one list of dependencies (also read by scripts/setup-debian
      # and tests/test_dependencies.py): a table per dependency with its role and
      # its nixpkgs attributes, space-separated, "" for none.
      dependencies = builtins.fromTOML (builtins.readFile ./dependencies.toml);
      words = text: builtins.filter (w: builtins.isString w && w != "") (builtins.split " +" text);
      nixNamesOfRole = role:
        builtins.concatMap (dep: words dep.nix) (builtins.filter (dep: dep.role == role) (builtins.attrValues dependencies));

      perSystem = system: pkgs:
        let
          # A nixpkgs attribute path of the list ("xorg.libXtst") as a package.
          attrOf = path: builtins.foldl' (set: name: set.${name}) pkgs (lib.splitString "." path);
          packagesOfRole = role: map attrOf (nixNamesOfRole role);
          # The one package of a named entry of the list.
          packageOf = name: attrOf dependencies.${name}.nix;

          stdenv = packageOf "compiler";
          python = (packageOf "python").withPackages (ps: map (name: ps.${name}) (nixNamesOfRole "python"));
          tracyClientDir = "${(packageOf "tracy").src}/public";
          validationLayers = "${packageOf "vulkan-validation-layers"}/share/vulkan/explicit_layer.d";

          # Vulkan through the pinned Mesa's lavapipe only, whatever GPU driver
          # the host has: the loader sees no other driver and no implicit layer.
          lvpIcd = "${packageOf "lavapipe"}/share/vulkan/icd.d/lvp_icd.${icdArch.${system}}.json";
          lavapipeEnv = {
            VK_DRIVER_FILES = lvpIcd;
            VK_ICD_FILENAMES = lvpIcd; # the name loaders before 1.3.207 read
            VK_LOADER_LAYERS_DISABLE = "~implicit~";
          };
          # Apps and the dev shell: lavapipe unless RT_USE_HOST_VULKAN=1, which
          # leaves driver selection to the host's Vulkan setup (a real GPU).
          lavapipeUnlessHostVulkan = ''
            if [ "''${RT_USE_HOST_VULKAN:-0}" != 1 ]; then
            ${lib.concatStringsSep "\n" (lib.mapAttrsToList (name: value: "  export ${name}=${lib.escapeShellArg value}") lavapipeEnv)}
            fi
          '';

          # A configure preset of CMakePresets.json, built, tested and installed.
          mkRaytracer = { preset, pname, tests ? true }:
            stdenv.mkDerivation {
              inherit pname version;
              src = self;

              nativeBuildInputs = packagesOfRole "build";
              # The libraries (bash among them: patchShebangs points the installed
              # scripts at it) and python, which patchShebangs also uses and which
              # runs pytest in checkPhase.
              buildInputs = packagesOfRole "library" ++ [ python ] ++ lib.optionals tests (packagesOfRole "test-library");
              # The programs the tests run: the window tests' Xvfb, xwininfo, xwd
              # and ImageMagick, ss for the loopback test.
              nativeCheckInputs = packagesOfRole "check";

              # The preset itself (generator, build type, flags, build/<preset>),
              # plus the install prefix, nixpkgs' Tracy client sources (used
              # where the preset sets RT_TRACY=ON; never fetched with cargo) and
              # the Vulkan loader's store path (the binary dlopens it, and
              # dlopen does not search the store).
              configurePhase = ''
                runHook preConfigure
                cmake --preset ${preset} -DCMAKE_INSTALL_PREFIX=$out \
                  -DRT_BUILD_TESTS=${if tests then "ON" else "OFF"} -DRT_TRACY_CLIENT_DIR=${tracyClientDir} -DRT_WINDOW=ON -DRT_EMBREE=ON \
                  -DRT_VULKAN_LOADER=${packageOf "vulkan-loader"}/lib/libvulkan.so.1
                cd build/${preset}
                runHook postConfigure
              '';
              # ninja's setup hook builds and installs in build/<preset>.

              doCheck = tests;
              env = lavapipeEnv // gitEnv // { VK_ADD_LAYER_PATH = validationLayers; };
              # The whole suite, as scripts/test runs it: GoogleTest via ctest, then pytest.
              checkPhase = ''
                runHook preCheck
                export HOME=$TMPDIR
                ctest --output-on-failure -j $NIX_BUILD_CORES
                # libX11 and libXtst for the window tests' resize and key press (ctypes).
                LD_LIBRARY_PATH=${lib.concatStringsSep ":" (map (p: "${p}/lib") (packagesOfRole "check-dlopen"))} \
                RT_BINARY=$PWD/raytracer RT_PYTHON=${python}/bin/python3 \
                  ${python}/bin/python3 -m pytest -p no:cacheprovider ../../tests
                runHook postCheck
              '';

              # Runs of the installed binary record the nixpkgs revision.
              postFixup = ''
                wrapProgram $out/bin/raytracer ${
                  lib.concatStringsSep " " (lib.mapAttrsToList (name: value: "--set ${name} ${lib.escapeShellArg value}") nixEnv)}
              '';

              meta = {
                description = "Ray tracer of sphere scenes with interchangeable CPU, SIMD and Vulkan renderers";
                mainProgram = "raytracer";
                platforms = systems;
              };
            };

          # The benchmark build: preset `profile` = `release` + RT_TRACY=ON (the
          # client only collects while a viewer is connected); tests in checkPhase.
          raytracer = mkRaytracer { preset = "profile"; pname = "raytracer"; };
          # -O0 as the thesis measured, for profiles that ask for it.
          raytracerPaperO0 = mkRaytracer { preset = "paper-o0"; pname = "raytracer-paper-o0"; tests = false; };

          share = "${raytracer}/share/raytracer";
          mkApp = name: text: pkgs.writeShellApplication {
            inherit name;
            runtimeInputs = [ python ];
            runtimeEnv = nixEnv // {
              RT_PYTHON = "${python}/bin/python3";
              # The bench runner uses these instead of building with CMake.
              RT_BINARY = "${raytracer}/bin/raytracer";
              RT_BINARY_PAPER_O0 = "${raytracerPaperO0}/bin/raytracer";
            };
            text = lavapipeUnlessHostVulkan + text;
          };
          wrappers = {
            default = mkApp "raytracer" ''exec ${raytracer}/bin/raytracer "$@"'';
            bench = mkApp "raytracer-bench" ''exec ${share}/scripts/bench "$@"'';
            report = mkApp "raytracer-report" ''exec ${share}/scripts/report.py "$@"'';
          };
        in
        {
          packages = {
            default = raytracer;
            inherit raytracer;
            paper-o0 = raytracerPaperO0;
          };

          apps = builtins.mapAttrs (_: wrapper: { type = "app"; program = lib.getExe wrapper; }) wrappers;

          devShells.default = (pkgs.mkShell.override { inherit stdenv; }) {
            inputsFrom = [ raytracer ];
            # tracy (GUI, tracy-capture, tracy-csvexport), vulkan-tools, the
            # validation layers, git; the tests' programs; scripts/lint's
            # clang-format 19 (with clangd) and ruff.
            packages = packagesOfRole "develop" ++ packagesOfRole "runtime" ++ packagesOfRole "check"
              ++ packagesOfRole "lint" ++ [ python ];
            env = nixEnv // {
              RT_PYTHON = "${python}/bin/python3";
              # cmake --preset profile builds nixpkgs' Tracy client (cmake/Tracy.cmake).
              RT_TRACY_CLIENT_DIR = tracyClientDir;
              VK_ADD_LAYER_PATH = validationLayers;
            };
            shellHook = lavapipeUnlessHostVulkan;
          };

          checks = {
            # The package's test suite runs in its checkPhase.
            raytracer = raytracer;
            # Syntax errors in the scripts (bash -n, a parse of every Python
            # file); formatting and lint are scripts/lint, in the dev shell.
            scripts-syntax = pkgs.runCommand "raytracer-scripts-syntax" { nativeBuildInputs = [ python ]; } ''
              cd ${self}
              for f in scripts/lib/*.sh; do bash -n "$f"; done
              for f in scripts/*; do
                if [ -f "$f" ]; then case "$(head -n1 "$f")" in *bash*) bash -n "$f" ;; esac; fi
              done
              python3 -c 'import ast, pathlib, sys; [ast.parse(p.read_text(), str(p)) for d in sys.argv[1:] for p in pathlib.Path(d).rglob("*.py")]' scripts tests
              touch $out
            '';
            # The app wrappers (writeShellApplication runs shellcheck on them).
            app-default = wrappers.default;
            app-bench = wrappers.bench;
            app-report = wrappers.report;
          };
        };

      outputsPerSystem = forAllSystems perSystem;
    in
    {
      packages = builtins.mapAttrs (_: o: o.packages) outputsPerSystem;
      apps = builtins.mapAttrs (_: o: o.apps) outputsPerSystem;
      devShells = builtins.mapAttrs (_: o: o.devShells) outputsPerSystem;
      checks = builtins.mapAttrs (_: o: o.checks) outputsPerSystem;
    };
}
