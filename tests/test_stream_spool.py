"""A streamed batch's spool (lcchain.studies.stream.TaskSpool) finds each key's first row exactly, whatever its
keys share (issue 35: a batch's memory flat in its number of netlists)."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest

from lcchain.core.errors import ParameterError
from lcchain.core.frozen import FrozenMap
from lcchain.core.json import JSON
from lcchain.studies.plan import Refusal
from lcchain.studies.store import Store
from lcchain.studies.stream import TaskSpool


def test_a_spool_marks_the_first_row_of_each_key_even_when_keys_share_their_first_bytes() -> None:
    keys = [hashlib.sha256(str(i).encode()).hexdigest() for i in range(600)]
    keys[10] = keys[500] = keys[3]  # a netlist given three times
    keys[20] = keys[7][:16] + "0" * 48  # the first 8 bytes of keys[7], another key
    keys[21] = keys[22] = keys[7][:16] + "1" * 48  # and another, given twice
    spool = TaskSpool()
    try:
        for index, key in enumerate(keys):
            spool.add(Refusal(index, FrozenMap({"netlist": str(index)}), "", key), key, str(index))
        expected = [int(key not in keys[:index]) for index, key in enumerate(keys)]
        assert spool.first() == expected
        assert [spool.key(i) for i in range(len(keys))] == keys
    finally:
        spool.close()


def test_a_listed_description_is_the_text_json_writes_and_is_compared_whole(tmp_path: Path) -> None:
    """The store writes a streamed batch's list of netlists a name at a time (Store.adopt's ``listed``): the text
    json.dumps writes of the whole description; a store of the same batch under another fingerprint is told apart
    from another batch's by the whole list."""
    names = ["a.cir", "sous dossier/b é.cir", "./c.cir"]
    description: dict[str, JSON] = {"command": "batch", "netlists": [], "allow_control": False, "backend": "batch"}
    rows = [(hashlib.sha256(name.encode()).hexdigest(), {"netlist": name}, name) for name in names]
    with Store(tmp_path / "s.sqlite") as store:
        store.adopt("plan-1", description, iter(rows), "ngspice 39", count=len(rows),
                    listed=("netlists", lambda: iter(names)))
        assert store.meta()["description"] == json.dumps({**description, "netlists": names})
        with pytest.raises(ParameterError, match="this very study"):
            store.check_plan("plan-2", description, len(rows), "ngspice 40", listed=("netlists", lambda: iter(names)))
        with pytest.raises(ParameterError, match="it holds another"):
            store.check_plan("plan-2", description, 2, "ngspice 40", listed=("netlists", lambda: iter(names[:2])))
