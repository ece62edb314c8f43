"""The views of an activity and of a run (docs/views.md): the flow graph of a script
(`scriptc graph`), the HTML report of a run, the trace as MCAP for Foxglove, and the session
summary for the therapist. Each module reads the IR or a run's trace and writes its format;
nothing here runs a session or prints."""
