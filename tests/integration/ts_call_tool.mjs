// A test helper beside examples/clients/typescript_client.mjs: call one tool through bagmcp with the MCP
// TypeScript SDK and print one JSON line: the server's instructions, the error flag and text of the answer.
// Usage: BAGMCP_URL=http://127.0.0.1:8080/mcp BAGMCP_TOKEN=secret node ts_call_tool.mjs TOOL '{"bag": "x"}'
import { Client } from "@modelcontextprotocol/sdk/client/index.js";
import { StreamableHTTPClientTransport } from "@modelcontextprotocol/sdk/client/streamableHttp.js";

const headers = { Authorization: `Bearer ${process.env.BAGMCP_TOKEN}` };
const transport = new StreamableHTTPClientTransport(new URL(process.env.BAGMCP_URL), { requestInit: { headers } });
const client = new Client({ name: "bagmcp-test", version: "1.0.0" });

await client.connect(transport);
try {
  const result = await client.callTool({ name: process.argv[2], arguments: JSON.parse(process.argv[3] ?? "{}") });
  const text = result.content.map((block) => block.text ?? "").join(" ");
  console.log(JSON.stringify({ instructions: client.getInstructions() ?? null, isError: result.isError ?? false, text }));
} finally {
  await client.close();
}
