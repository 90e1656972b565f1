"""The arguments of search_messages (the tool's declaration is in tools/search_tools.py), in the order the tool
lists them; search.py and search_logs.py read them."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, Field, JsonValue

from bagmcp_bag_store.queries.conditions import Condition
from bagmcp_kit.arguments import BagRef, TimeArg, TopicName

ConditionValue = Annotated[
    JsonValue,
    Field(description="number, text, [low, high] (between) or {x, y, radius} m (near_position)"),
]


class SearchParams(BaseModel):
    bag: BagRef
    topic: TopicName
    condition: Condition
    value: ConditionValue = None
    field: Annotated[str | None, Field(description="path to test (default: the obvious one)")] = None
    start: TimeArg | None = None
    end: TimeArg | None = None
    limit: Annotated[int, Field(ge=1, le=200, description="matches to show")] = 20
    correlate_topic: Annotated[str | None, Field(description="add its nearest message (or /topic.path)")] = None
    correlate_tolerance_s: Annotated[float, Field(gt=0, le=60, description="max time apart")] = 0.1
