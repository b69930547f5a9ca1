"""Sample batches as a pandas DataFrame (pandas is optional)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Iterable

if TYPE_CHECKING:
    from ._nclink import SampleBatch


def dataframe(batches: Iterable["SampleBatch"]) -> Any:
    """One row per sample row: a UTC DatetimeIndex ("time"), a "channel" column and one
    column per point id. Needs pandas (Debian: python3-pandas); ImportError says so."""
    try:
        import pandas as pd  # type: ignore[import]
    except ImportError as missing:
        raise ImportError("nclink.dataframe needs pandas: apt-get install python3-pandas "
                          "(or pip install pandas)") from missing
    frames = []
    for batch in batches:
        if len(batch) == 0:
            continue
        columns = batch.columns
        columns["channel"] = [batch.channel] * len(batch)
        index = pd.to_datetime(batch.times_ms, unit="ms", utc=True)
        frames.append(pd.DataFrame(columns, index=pd.DatetimeIndex(index, name="time")))
    if not frames:
        return pd.DataFrame(columns=["channel"], index=pd.DatetimeIndex([], name="time", tz="UTC"))
    frame = pd.concat(frames)
    return frame[["channel"] + [c for c in frame.columns if c != "channel"]]
