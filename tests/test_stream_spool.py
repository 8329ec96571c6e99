"""A streamed batch's spool (lcchain.studies.stream.TaskSpool) finds each key's first row exactly, whatever its
keys share (issue 35: a batch's memory flat in its number of netlists)."""

from __future__ import annotations

import hashlib

from lcchain.core.frozen import FrozenMap
from lcchain.studies.plan import Refusal
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
