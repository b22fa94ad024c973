"""The transformation f of thesis figure 7.3 and its inverse, as lists of small passes over the tree and the world."""

from __future__ import annotations

import dataclasses
from typing import Callable

from orc_rpl.syntax import nodes as n
from orc_rpl.errors import InternalError, OrcError
from orc_rpl.world import World, restore_model_attributes, split_model_attributes
from orc_rpl.world.online import ModelStore
from orc_rpl.transform.declarations import (absorb_declarations, absorbable, collapse_tools, declare_frames, declare_positions,
                                            leading_comments)
from orc_rpl.transform.frames import insert_frame_blocks, remove_frame_blocks
from orc_rpl.transform.job import Job
from orc_rpl.transform.new_world import absorb_new
from orc_rpl.transform.references import resolve_positions, unresolve_positions

Pass = Callable[[Job], Job]

#: How many shorter runs of declarations are tried before none (each try is one transformation).
MAX_CANDIDATES = 8


def refuse_clashes(job: Job) -> Job:
    """An off-line program may not declare a name the world also names, nor a position relative to a world frame."""
    names = job.named().names
    assert names is not None
    for stmt in job.program.body:
        if isinstance(stmt, n.Declaration) and stmt.name.id in names.entity:
            raise job.error(stmt.name, f"'{stmt.name.id}' is declared in the program and is also '{names.entity[stmt.name.id]}' "
                                       f"of the world model", "rename one of them")
        if isinstance(stmt, n.Declaration) and stmt.frame is not None and stmt.frame.id in job.world._by_name():
            raise job.error(stmt.frame, f"positions relative to the world's frame '{stmt.frame.id}' belong in the world model",
                            f"add '{stmt.name.id}' to the frames of '{stmt.frame.id}' and write {stmt.frame.id}.{stmt.name.id}")
    return job.named()


def reduce_world(job: Job) -> Job:
    """The on-line world: spatial and soft attributes stay; model attributes become keys into the off-line model."""
    online, store = split_model_attributes(job.world)
    return dataclasses.replace(job, world=online, store=store)


def restore_world(job: Job) -> Job:
    """The off-line world back: every model key replaced by the model attributes it stands for."""
    if job.store is None:
        return job
    return dataclasses.replace(job, world=restore_model_attributes(job.world, job.store), store=None)


#: Off-line -> on-line (thesis 7.3).
TO_ONLINE: tuple[Pass, ...] = (refuse_clashes, resolve_positions, insert_frame_blocks, declare_positions, collapse_tools,
                               declare_frames)
#: On-line -> off-line, given the off-line world the program came from.
TO_OFFLINE: tuple[Pass, ...] = (restore_world, absorb_declarations, remove_frame_blocks, unresolve_positions)


def run(job: Job, passes: tuple[Pass, ...]) -> Job:
    """The passes applied in order."""
    for step in passes:
        job = step(job)
    return job


def to_online(program: n.Program, world: World, path: str = "<program>", source: str | None = None, *,
              reduce: bool = False) -> Job:
    """The on-line program (declarations, FRAME blocks, on-line names); with `reduce`, also the reduced world
    and its model store (reading the reduced world back costs as much as reading the world, so only on request)."""
    job = run(Job(program, world, path, source), TO_ONLINE)
    return reduce_world(job) if reduce else job


def to_offline(program: n.Program, world: World | None, path: str = "<program>", store: ModelStore | None = None, *,
               move_declarations: bool = False) -> Job:
    """The off-line program and world model. Given the world the program came from, edits made on-line go into it;
    without one, the world is made from the program's declarations, as far as the on-line text then comes back exactly,
    or, with `move_declarations` (what `orc convert` does), also those standing after other statements."""
    if world is not None:
        return run(Job(program, world, path, store=store), TO_OFFLINE)
    return _from_declarations(program, path, move_declarations)


def _from_declarations(program: n.Program, path: str, move_declarations: bool = False) -> Job:
    """An on-line program that was never off-line: take as many declarations into a new world as come back.

    Candidates, best first (the first two with `move_declarations` only): every top-level declaration the world can
    hold, wherever it stands (after an INSTALL, as in demo_pallet), coming back exactly, then coming back with only
    the declarations in another place (the
    transformation declares positions at the top, in first-use order; declarations are global wherever they stand,
    so the program means the same); then the leading run of declarations and shorter runs (at most MAX_CANDIDATES)
    coming back exactly, and at last none, which is always exact. Each with its FRAME blocks removed, then kept.
    """
    body = program.body
    start = leading_comments(body)
    end = start
    while end < len(body) and absorbable(body[end], new=True):
        end += 1
    anywhere = frozenset(i for i, stmt in enumerate(body) if absorbable(stmt, new=True))
    candidates: list[tuple[frozenset[int], Callable[[n.Program, frozenset[int]], bool]]] = []
    if anywhere and move_declarations:
        candidates += [(anywhere, lambda back, chosen: back == program), (anywhere, lambda back, chosen: _same_but_declaration_places(back, program, chosen))]
    counts = list(range(end - start, max(end - start - MAX_CANDIDATES, 0), -1)) + [0]
    candidates += [(frozenset(range(start, start + count)), lambda back, chosen: back == program) for count in counts]
    for chosen, same in candidates:
        for strip in (True, False) if chosen else (False,):
            try:
                job = absorb_new(program, chosen, path)
                if strip:
                    job = remove_frame_blocks(job)
                job = unresolve_positions(job)
                back = run(Job(job.program, job.world, path), TO_ONLINE)
            except OrcError:
                continue  # a candidate the world model or the names refuse: try a smaller one
            if same(back.program, chosen):
                return dataclasses.replace(job, names=None, chains={})
    raise InternalError(f"no exact off-line form of {path} found")


def _same_but_declaration_places(program: n.Program, original: n.Program, chosen: frozenset[int]) -> bool:
    """`program` is `original` with the chosen declarations moved (they come back declared in another place)."""
    declared = [original.body[i] for i in sorted(chosen)]
    rest = [stmt for i, stmt in enumerate(original.body) if i not in chosen]
    back_rest = [stmt for stmt in program.body if stmt not in declared]
    return back_rest == rest and sorted(map(repr, declared)) == sorted(repr(s) for s in program.body if s in declared)
