"""The API 617 lateral audit: undamped critical speed map, the standard's unbalance, Level I
and Level II stability and the audit as one call."""
