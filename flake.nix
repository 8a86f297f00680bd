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

      perSystem = system: pkgs:
        let
          python = pkgs.python3.withPackages (ps: [ ps.pandas ps.matplotlib ps.rich ps.pytest ]);
          tracyClientDir = "${pkgs.tracy.src}/public";
          validationLayers = "${pkgs.vulkan-validation-layers}/share/vulkan/explicit_layer.d";

          # Vulkan through the pinned Mesa's lavapipe only, whatever GPU driver
          # the host has: the loader sees no other driver and no implicit layer.
          lvpIcd = "${pkgs.mesa}/share/vulkan/icd.d/lvp_icd.${icdArch.${system}}.json";
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
            pkgs.gcc14Stdenv.mkDerivation {
              inherit pname version;
              src = self;

              nativeBuildInputs = [ pkgs.cmake pkgs.ninja pkgs.pkg-config pkgs.glslang pkgs.makeWrapper ];
              # bash and python: patchShebangs points the installed scripts at them;
              # python also runs pytest in checkPhase.
              buildInputs = [
                pkgs.bash
                pkgs.glm
                pkgs.nlohmann_json
                pkgs.cli11
                pkgs.stb
                pkgs.onetbb
                pkgs.libhwy
                pkgs.vulkan-headers
                pkgs.vulkan-loader
                pkgs.glfw # the live window (--window, RT_WINDOW=ON)
                python
              ] ++ lib.optionals tests [ pkgs.gtest ];
              # The window tests (tests/window) run under their own Xvfb and
              # read the X display with xwininfo, xwd and ImageMagick.
              nativeCheckInputs = [ pkgs.xorg.xorgserver pkgs.xorg.xwininfo pkgs.xorg.xwd pkgs.imagemagick ];

              # The preset itself (generator, build type, flags, build/<preset>),
              # plus the install prefix, nixpkgs' Tracy client sources (used
              # where the preset sets RT_TRACY=ON; never fetched with cargo) and
              # the Vulkan loader's store path (the binary dlopens it, and
              # dlopen does not search the store).
              configurePhase = ''
                runHook preConfigure
                cmake --preset ${preset} -DCMAKE_INSTALL_PREFIX=$out \
                  -DRT_BUILD_TESTS=${if tests then "ON" else "OFF"} -DRT_TRACY_CLIENT_DIR=${tracyClientDir} -DRT_WINDOW=ON \
                  -DRT_VULKAN_LOADER=${pkgs.vulkan-loader}/lib/libvulkan.so.1
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
                LD_LIBRARY_PATH=${pkgs.xorg.libX11}/lib:${pkgs.xorg.libXtst}/lib \
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

          devShells.default = (pkgs.mkShell.override { stdenv = pkgs.gcc14Stdenv; }) {
            inputsFrom = [ raytracer ];
            packages = [
              pkgs.tracy # tracy (GUI), tracy-capture, tracy-csvexport
              pkgs.vulkan-tools
              pkgs.vulkan-validation-layers
              pkgs.clang-tools
              pkgs.git
              python
            ];
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
            # The project has no formatter or linter yet; this catches syntax
            # errors in its scripts (bash -n, a parse of every Python file).
            scripts-syntax = pkgs.runCommand "raytracer-scripts-syntax" { nativeBuildInputs = [ python ]; } ''
              cd ${self}
              for f in scripts/lib/*.sh; do bash -n "$f"; done
              for f in scripts/*; do
                if [ -f "$f" ]; then case "$(head -n1 "$f")" in *bash*) bash -n "$f" ;; esac; fi
              done
              # Python files, except the bash ones named .py (scripts/report.py), checked above.
              python3 -c 'import ast, pathlib, sys; [ast.parse(p.read_text(), str(p)) for d in sys.argv[1:] for p in pathlib.Path(d).rglob("*.py") if "bash" not in p.read_text().partition("\n")[0]]' scripts tests
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
