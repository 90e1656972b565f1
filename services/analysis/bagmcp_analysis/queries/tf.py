"""get_tf_tree and lookup_transform over the bag's TF topics (static and dynamic, old tf too)."""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import BaseModel, Field

from bagmcp_analysis.reports.tf import EdgeOut, TfTreeReport, TransformReport
from bagmcp_analysis.tf.tree import TfBuffer, TfSample
from bagmcp_kit.arguments import BagRef, TimeArg
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.carry import carried
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.index import TransformRows, decode_transforms, tf_connections
from bagmcp_shared.jobs import Progress, spans

Frame = Annotated[str, Field(description="TF frame id")]


class TfTreeParams(BaseModel):
    """The arguments of get_tf_tree."""

    bag: BagRef
    time: Annotated[TimeArg | None, Field(description="default: whole bag")] = None


class TransformParams(BaseModel):
    """The arguments of lookup_transform."""

    bag: BagRef
    target_frame: Frame
    source_frame: Frame
    time: Annotated[TimeArg | None, Field(description="default: end of the bag")] = None


def _topics(ob: OpenBag) -> list[str]:
    topics = sorted({c.topic for c in tf_connections(ob.reader)})
    if not topics:
        raise ArgumentError(f"{ob.name} has no TF topic (tf2_msgs/TFMessage or tf/tfMessage)")
    return topics


def _samples(rows: TransformRows) -> list[TfSample]:
    frames = rows.frames
    return [
        TfSample(
            t_ns=int(rows.t_ns[i]),
            parent=frames[int(rows.parent[i])],
            child=frames[int(rows.child[i])],
            translation=(float(rows.translation[i, 0]), float(rows.translation[i, 1]), float(rows.translation[i, 2])),
            rotation=tuple(float(v) for v in rows.rotation[i]),  # type: ignore[arg-type]
            static=bool(rows.static[i]),
        )
        for i in range(len(rows))
    ]


def read_buffer(ob: OpenBag, progress: Progress) -> tuple[TfBuffer, list[str]]:
    """Every transform of the bag (from the index when built), as a TF buffer."""
    topics = _topics(ob)
    samples: list[TfSample] = []
    for topic, step in zip(topics, spans(progress, len(topics)), strict=True):
        rows = ob.index.transforms(topic) if ob.index is not None else None
        if rows is None:
            connections = [c for c in tf_connections(ob.reader) if c.topic == topic]
            rows = decode_transforms(ob.reader, connections, progress=step)
        samples += _samples(rows)
    return TfBuffer(samples), topics


def get_tf_tree(access: BagAccess, params: TfTreeParams, progress: Progress) -> TfTreeReport:
    with access.open(params.bag) as ob:
        buffer, topics = read_buffer(ob, progress)
        stamp = ob.time(params.time) if params.time is not None else None
        tree = buffer.tree(stamp)
        notes = [f"{tree.ignored_samples} unusable transforms were left out"] if tree.ignored_samples else []
        return TfTreeReport(
            bag=ob.name,
            topics=topics,
            time=ob.instant(stamp) if stamp is not None else None,
            frames=tree.order,
            roots=tree.roots,
            edges=[
                carried(
                    EdgeOut,
                    e,
                    first=ob.instant(e.first_ns),
                    last=ob.instant(e.last_ns),
                    nearest=ob.instant(e.nearest_ns) if e.nearest_ns is not None else None,
                )
                for e in tree.edges
            ],
            multiple_parents=tree.multiple_parents,
            notes=notes,
        )


def lookup_transform(access: BagAccess, params: TransformParams, progress: Progress) -> TransformReport:
    with access.open(params.bag) as ob:
        buffer, _ = read_buffer(ob, progress)
        stamp = ob.time(params.time) if params.time is not None else ob.end_ns
        try:
            found = buffer.lookup(params.target_frame, params.source_frame, stamp)
        except ValueError as err:
            raise ArgumentError(str(err)) from err
        return TransformReport(
            bag=ob.name,
            target_frame=params.target_frame,
            source_frame=params.source_frame,
            time=ob.instant(stamp),
            translation_m=list(found.translation),
            rotation=list(found.rotation),
            roll_deg=math.degrees(found.roll_rad),
            pitch_deg=math.degrees(found.pitch_rad),
            yaw_deg=math.degrees(found.yaw_rad),
            chain=found.chain,
            interpolated=found.interpolated,
            extrapolated_s=found.extrapolated_s,
        )


def tf_is_small(access: BagAccess, bag: str) -> bool:
    with access.open(bag) as ob:
        topics = _topics(ob)
        indexed = ob.index is not None and all(t in ob.index.transform_topics() for t in topics)
        return indexed or all(ob.short(t) for t in topics)
