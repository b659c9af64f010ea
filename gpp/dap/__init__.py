"""`gpp dap`: a Debug Adapter Protocol server for golog++ runs.

Shape (what the editors' extension and the trace backend build on):

* gpp.dap.protocol: the wire format (Content-Length framing), `Connection` (one writer shared
  by threads), `DapError` (a request that cannot be done: an error response with its message);
* gpp.dap.server: `DebugServer`, the protocol loop (the main thread of `gpp dap`): one handler
  per request, the breakpoint table, and a `SessionBackend` it asks for everything it shows;
  it is the backend's `Client` (stopped, output, ended events);
* gpp.dap.main: serving one session on stdio or on a loopback `--tcp` port;
* gpp.dap.backend: the `SessionBackend` interface (stack, scopes, variables, evaluate; resume
  with continue/next/stepIn/stepOut, and stepBack/reverseContinue where its `capabilities`
  say so; pause; terminate) and the values it answers with (StackFrame, Scope, Variable,
  Evaluated, Stop);
* gpp.dap.launch: `launch`'s arguments -> a backend: `"program"` makes the live backend,
  `"trace": "run.jsonl"` the trace backend of module `gpp.dap.replay`
  (`make_trace_backend(args, server) -> SessionBackend`);
* gpp.dap.live: `LiveBackend`, a run control (gpp.runtime.control) of a run made by
  gpp.run.runner.run_program on a thread of its own;
* gpp.dap.program: `DebugProgram`, the checked program indexed for the debugger (statements by
  line, the procedure of each) and expressions typed in the editor checked by the real front
  end in the scope of a statement; gpp.dap.breakpoints: the breakpoint table; gpp.dap.stack:
  the call stack read from a continuation; gpp.dap.variables: values, fluents, activities and
  the plan as DAP variables.
"""
