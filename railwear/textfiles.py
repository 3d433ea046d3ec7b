"""Text files a user gives railwear (layer 0): UTF-8, a byte-order mark dropped."""

from railwear.errors import ScenarioError


def decode_text(data: bytes, source, error=ScenarioError):
    """UTF-8 text of a file (a byte-order mark is dropped); anything else is refused (``error``)
    naming the line and column of the first bad byte."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        column = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
        raise error(f"{source}: line {line}, column {column}: not UTF-8 text "
                            f"(byte 0x{data[e.start]:02x}); save the file as UTF-8") from None
