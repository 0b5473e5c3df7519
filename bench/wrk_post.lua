-- wrk_post.lua -- wrk script: POST one fixed body, report rate and tail.
--
-- The body is read once per wrk thread from the file named by the
-- environment variable WRK_BODY (wrk runs this file in every thread's own
-- Lua state); its Content-Type comes from WRK_TYPE (application/json by
-- default). At the end one machine-readable line is printed for bench/run:
--   WRK requests=N seconds=S rps=R p50_ms=.. p90_ms=.. p99_ms=.. max_ms=..
--       non2xx=N connect_err=N read_err=N write_err=N timeouts=N
local path = os.getenv("WRK_BODY")
local f = assert(io.open(path or "", "rb"), "WRK_BODY names no readable file")
wrk.method = "POST"
wrk.body = f:read("*a")
f:close()
wrk.headers["Content-Type"] = os.getenv("WRK_TYPE") or "application/json"

function done(summary, latency, requests)
  local s = summary.duration / 1e6
  local e = summary.errors
  io.write(string.format(
    "WRK requests=%d seconds=%.3f rps=%.1f p50_ms=%.3f p90_ms=%.3f " ..
    "p99_ms=%.3f max_ms=%.3f non2xx=%d connect_err=%d read_err=%d " ..
    "write_err=%d timeouts=%d\n",
    summary.requests, s, summary.requests / s,
    latency:percentile(50) / 1000, latency:percentile(90) / 1000,
    latency:percentile(99) / 1000, latency.max / 1000,
    e.status, e.connect, e.read, e.write, e.timeout))
end
