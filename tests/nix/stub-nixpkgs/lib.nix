# The nixpkgs lib functions flake.nix uses, written to behave like nixpkgs'
# for the arguments flake.nix gives them (stricter where that is cheap:
# getExe requires meta.mainProgram).
rec {
  genAttrs = names: f: builtins.listToAttrs (map (name: { inherit name; value = f name; }) names);

  mapAttrsToList = f: attrs: map (name: f name attrs.${name}) (builtins.attrNames attrs);

  inherit (builtins) concatStringsSep;

  # Like nixpkgs' for a one-character separator: the parts between them.
  splitString = sep: text: builtins.filter builtins.isString (builtins.split (escapeRegex sep) text);
  escapeRegex = builtins.replaceStrings [ "." "+" "*" "?" "[" "]" "(" ")" "{" "}" "|" "^" "$" "\\" ] [ "\\." "\\+" "\\*" "\\?" "\\[" "\\]" "\\(" "\\)" "\\{" "\\}" "\\|" "\\^" "\\$" "\\\\" ];

  optionals = cond: list: if cond then list else [ ];

  optionalString = cond: string: if cond then string else "";

  # Like nixpkgs: safe strings stay as they are, others are single-quoted.
  escapeShellArg = arg:
    let string = toString arg; in
    if builtins.match "[[:alnum:],._+:@%/-]+" string == null
    then "'${builtins.replaceStrings [ "'" ] [ "'\\''" ] string}'"
    else string;

  getExe = drv: "${drv}/bin/${drv.meta.mainProgram}";
}
