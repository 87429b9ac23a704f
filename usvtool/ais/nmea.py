"""NMEA 0183 AIS logs: ``!AIVDM`` / ``!AIVDO`` sentences with a time on each line, decoded with
pyais.

A line's time is its NMEA 4.10 tag block's receiver time (``\\c:1641168007*hh\\!AIVDM,...``, Unix
seconds, or milliseconds when above 1e11), or a leading time column before the sentence
(``2022-01-03T00:00:07Z,!AIVDM,...`` or ``1641168007.25 !AIVDM,...``: ISO 8601, UTC unless a zone
is given, or Unix seconds; separated by a comma, semicolon, tab or spaces). A fragment of a
multi-sentence message without a time of its own takes that of the message's first fragment; a
message with no time at all is refused, in one line naming the file and the line.

Fragments are joined by their sequential message id and channel (ITU-R M.1371 / IEC 61162-1:
fragment 1 of n starts a message, the others must follow in order); a message left incomplete
is counted, not decoded. Position reports are types 1-3 (class A), 18 and 19 (class B) and 27
(long range); static data types 5, 19 and 24 (name, ship type, dimensions: length = to bow + to
stern, beam = to port + to starboard, a sum of 0 meaning not available); the static data are
joined to the positions by MMSI when the tracks are made (:mod:`usvtool.ais.clean`). Lines that
are not AIS sentences, sentences with a bad checksum and messages pyais cannot decode are counted
(``not_ais``, ``bad_checksum``, ``undecodable``), as are the message types that are neither
(``other_types``): a receiver's log always holds some.
"""

from __future__ import annotations

import io
import re
from datetime import datetime, timezone

import numpy as np

from usvtool.ais.fixes import Fixes, fixes
from usvtool.errors import UsvError

POSITION_TYPES = frozenset({1, 2, 3, 18, 19, 27})
STATIC_TYPES = frozenset({5, 19, 24})
#: A tag block's c: above this is milliseconds.
MILLISECONDS_ABOVE = 1e11
_SENTENCE = re.compile(r"[!$][A-Z]{2}VD[MO],")
_SEPARATOR = " ,;\t"
#: A UTF-8 byte order mark read as latin-1.
BOM = "\xef\xbb\xbf"


def detect(first: str) -> bool:
    """Whether a file whose first non-empty line is ``first`` is an NMEA log."""
    return bool(first) and (first.startswith("\\") or _SENTENCE.search(first[:80]) is not None)


def split_time(path, number: int, line: str) -> tuple[str, int | None]:
    """The sentence of a log line (with its tag block) and the line's time (ns UTC, None when
    it has none); one line for a leading time that is not one."""
    if line.startswith("\\"):
        return line, _tag_time(line)
    found = _SENTENCE.search(line)
    if found is None or found.start() == 0:
        return line, None
    text = line[: found.start()].rstrip(_SEPARATOR)
    try:
        return line[found.start():], parse_time(text)
    except ValueError:
        raise UsvError(f"{path}: line {number}, column time: {text[:40]!r} is not a time (ISO "
                       "8601 or Unix seconds)") from None  # fmt: skip


def _tag_time(line: str) -> int | None:
    """The receiver time (ns) of a line's tag block, None without one (or a bad checksum)."""
    end = line.find("\\", 1)
    block = line[1:end] if end > 0 else ""
    body, _, check = block.partition("*")
    if not check or _checksum(body) != check.strip().upper():
        return None
    for field in body.split(","):
        key, _, value = field.partition(":")
        if key == "c":
            try:
                seconds = float(value)
            except ValueError:
                return None
            if seconds > MILLISECONDS_ABOVE:
                seconds /= 1000.0
            return round(seconds * 1e9)
    return None


def _checksum(body: str) -> str:
    x = 0
    for ch in body.encode("ascii", "replace"):
        x ^= ch
    return f"{x:02X}"


def parse_time(text: str) -> int:
    """Nanoseconds since the epoch of Unix seconds or an ISO 8601 time (UTC unless a zone is
    given); ValueError otherwise.

    >>> parse_time("1641168007.5"), parse_time("2022-01-03T00:00:07Z")
    (1641168007500000000, 1641168007000000000)
    """
    try:
        return round(float(text) * 1e9)
    except ValueError:
        pass
    stamp = datetime.fromisoformat(text.strip().replace("Z", "+00:00"))
    if stamp.tzinfo is None:
        stamp = stamp.replace(tzinfo=timezone.utc)
    epoch = datetime(1970, 1, 1, tzinfo=timezone.utc)
    delta = stamp - epoch
    return (delta.days * 86_400 + delta.seconds) * 1_000_000_000 + delta.microseconds * 1000


def read(path) -> Fixes:
    """The fixes of an NMEA log (module docstring)."""
    from pyais.exceptions import InvalidNMEAMessageException, UnknownMessageException
    from pyais.messages import AISSentence, NMEASentenceFactory

    from usvtool.csvtable import open_binary

    counts = {"lines": 0, "not_ais": 0, "bad_checksum": 0, "incomplete": 0, "undecodable": 0,
              "other_types": 0}  # fmt: skip
    positions: list[tuple] = []
    statics: list[tuple] = []
    pending: dict[tuple, tuple[list, int]] = {}  # (talker, channel, seq id): fragments, time
    with io.TextIOWrapper(open_binary(path), encoding="latin-1", newline="") as stream:
        for number, raw in enumerate(stream, start=1):
            line = raw.removeprefix(BOM).strip() if number == 1 else raw.strip()
            if not line.isascii():
                counts["not_ais"] += 1
                continue
            if not line:
                continue
            counts["lines"] += 1
            sentence_text, time = split_time(path, number, line)
            try:
                sentence = NMEASentenceFactory.produce(sentence_text.encode())
            except (InvalidNMEAMessageException, UnknownMessageException, ValueError):
                counts["not_ais"] += 1
                continue
            if not isinstance(sentence, AISSentence):
                counts["not_ais"] += 1
                continue
            if not sentence.is_valid:
                counts["bad_checksum"] += 1
                continue
            key = (sentence.talker, sentence.channel, sentence.seq_id)
            if sentence.frag_cnt > 1:
                parts, first_time = pending.pop(key, ([], time))
                if sentence.frag_num == 1:
                    if parts:
                        counts["incomplete"] += 1
                    parts, first_time = [], time
                elif sentence.frag_num != len(parts) + 1:
                    counts["incomplete"] += 1
                    continue
                parts.append(sentence)
                if time is None:
                    time = first_time
                if len(parts) < sentence.frag_cnt:
                    pending[key] = (parts, first_time if first_time is not None else time)
                    continue
                sentence = AISSentence.assemble_from_iterable(parts)
                time = first_time if first_time is not None else time
            if time is None:
                raise UsvError(f"{path}: line {number}: no time (a tag block's c: field or a "
                               "leading time column)")  # fmt: skip
            try:
                message = sentence.decode()
            except Exception:  # pyais raises many kinds on a corrupt payload
                counts["undecodable"] += 1
                continue
            kind = message.msg_type
            if kind not in POSITION_TYPES and kind not in STATIC_TYPES:
                counts["other_types"] += 1
                continue
            if kind in POSITION_TYPES:
                positions.append((message.mmsi, time, message.lon, message.lat,
                                  message.speed, message.course,
                                  getattr(message, "heading", 511)))  # fmt: skip
            if kind in STATIC_TYPES:
                statics.append(_static(message, time))
    counts["incomplete"] += len(pending)
    if not positions and counts["lines"] and counts["not_ais"] == counts["lines"]:
        raise UsvError(f"{path}: no AIS sentence (!AIVDM or !AIVDO) in {counts['lines']} lines")
    p = np.array(positions, float).reshape(-1, 7)
    s = [r[:4] for r in statics]
    st = np.array(s, float).reshape(-1, 4)
    return fixes(np.array([r[0] for r in positions], np.int64),
                 np.array([r[1] for r in positions], np.int64), p[:, 2], p[:, 3], p[:, 4],
                 p[:, 5], p[:, 6], np.array([r[0] for r in statics], np.int64),
                 np.array([r[1] for r in statics], np.int64), st[:, 2], st[:, 3],
                 [r[4] for r in statics], np.array([r[5] for r in statics], np.int64),
                 counts)  # fmt: skip


def _static(message, time: int) -> tuple:
    """(mmsi, time, length, beam, name, ship type) of a static report; NaN, "" and 0 for what
    it does not carry (a type 24 part A has only the name, part B the rest)."""
    dims = [getattr(message, k, None) for k in ("to_bow", "to_stern", "to_port", "to_starboard")]
    if None in dims:
        length = beam = np.nan
    else:
        bow, stern, port, starboard = (int(d) for d in dims)
        length = bow + stern if bow + stern > 0 else np.nan
        beam = port + starboard if port + starboard > 0 else np.nan
    name = getattr(message, "shipname", None) or ""
    ship_type = int(getattr(message, "ship_type", 0) or 0)
    return message.mmsi, time, length, beam, name, ship_type
