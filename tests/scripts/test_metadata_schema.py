"""The nested keys of the run metadata (run_metadata[].fields in
schema/rt_schema.json): how a sidecar is checked against them. The binary's
own sidecars are checked in tests/app/test_raytracer_cli.py."""

import pytest

from rtbench import schema


def conforming_sidecar() -> dict:
    """A sidecar with every key the schema lists, at every depth; the
    optional objects filled, libraries keyed by library name."""

    def filled(fields: list[dict]) -> dict:
        return {f["name"]: filled(f["fields"]) if "fields" in f else 0 for f in fields}

    meta = filled(schema.schema()["run_metadata"])
    meta["libraries"] = {"oneTBB": "2021.8.0"}
    meta["outputs"]["frames"] = [meta["outputs"]["frames"], dict(meta["outputs"]["frames"])]
    return meta


def test_a_sidecar_with_the_schema_keys_conforms():
    meta = conforming_sidecar()
    assert schema.metadata_key_problems(meta) == []
    for optional in ("accel_structure", "device", "window"):
        meta[optional] = None
    meta["build"]["nix"] = None
    assert schema.metadata_key_problems(meta) == []


@pytest.mark.parametrize(
    "edit, problem",
    [
        (lambda m: m["host"].update(cpu_flags="avx2"), "host.cpu_flags: written, not in the schema"),
        (lambda m: m["device"].pop("api_version"), "device.api_version: in the schema, not written"),
        (lambda m: m["build"]["nix"].update(system="x86_64-linux"), "build.nix.system: written, not in the schema"),
        (lambda m: m["outputs"]["frames"][1].pop("file"), "outputs.frames[1].file: in the schema, not written"),
        (lambda m: m.update(scene="default"), "scene: not an object, but the schema lists its fields"),
        (lambda m: m.update(run_id={"stamp": 1}), "run_id: an object, but the schema lists no fields for it"),
        (lambda m: m.update(extra=1), "extra: written, not in the schema"),
    ],
)
def test_a_key_outside_the_schema_or_missing_from_the_sidecar_is_named(edit, problem):
    meta = conforming_sidecar()
    edit(meta)
    assert schema.metadata_key_problems(meta) == [problem]


def test_fields_are_read_by_path():
    assert "cpu_model" in schema.run_metadata_fields("host")
    assert schema.run_metadata_fields("build", "nix") == ["nixpkgs_rev"]
    assert schema.run_metadata_fields("libraries") == []
    with pytest.raises(KeyError, match=r"host\.gpu"):
        schema.run_metadata_fields("host", "gpu")
