# A stand-in for nixpkgs, used only by tests/nix/test_flake.py
# (`--override-input nixpkgs path:<this directory>`) to check offline that the
# project's flake.nix evaluates and has the expected outputs.
#
# It offers exactly the lib functions and package attributes flake.nix uses,
# under their nixpkgs names; every package is a cheap derivation that is never
# built. It proves the flake's shape, not that real nixpkgs builds it: a name
# added here must first be checked against nixpkgs at the pinned revision.
{
  description = "Stub of nixpkgs' lib and legacyPackages for offline shape checks";

  outputs = { self }:
    let
      lib = import ./lib.nix;
      systems = [ "x86_64-linux" "aarch64-linux" ];
    in
    {
      inherit lib;
      legacyPackages = lib.genAttrs systems (system: import ./pkgs.nix { inherit lib system; });
    };
}
