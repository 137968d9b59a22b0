"""
The parts of ``mouse_record``, one idea a module, below the thin command ``cli/record.py``.

- ``received``: the recorded topics and one message as received (serialized CDR);
- ``capture``: the recording node, the anchor read from the recorded node, the progress line;
- ``rows``: messages to CSV rows (one per tick) and the CSV file;
- ``figure``: the PNG figure (matplotlib, no display);
- ``mcap_file``: the MCAP file and the ``ros2msg`` schemas it carries;
- ``outputs``: the files a recording writes, checked for writing before it starts.
"""
