// List bagmcp's tools and ask `bag_info` about one bag, with the MCP TypeScript SDK (@modelcontextprotocol/sdk).
// Usage: npm install && BAGMCP_URL=http://127.0.0.1:8000/mcp BAGMCP_TOKEN=secret node typescript_client.mjs BAG
import { Client } from "@modelcontextprotocol/sdk/client/index.js";
import { StreamableHTTPClientTransport } from "@modelcontextprotocol/sdk/client/streamableHttp.js";

const url = new URL(process.env.BAGMCP_URL ?? "http://127.0.0.1:8000/mcp");
const token = process.env.BAGMCP_TOKEN;
const headers = token ? { Authorization: `Bearer ${token}` } : {};
const transport = new StreamableHTTPClientTransport(url, { requestInit: { headers } });
const client = new Client({ name: "bagmcp-example", version: "1.0.0" });

await client.connect(transport);
try {
  const { tools } = await client.listTools();
  console.log("tools:", tools.map((tool) => tool.name).join(", "));
  const result = await client.callTool({ name: "bag_info", arguments: { bag: process.argv[2] } });
  if (result.isError) {
    // a tool error: the text says what to do next
    console.error("bag_info failed:", result.content.map((block) => block.text ?? "").join(" "));
    process.exitCode = 1;
  } else {
    const info = result.structuredContent;
    console.log(`${info.name}: ${info.message_count} messages on ${info.topics.length} topics`);
  }
} finally {
  await client.close();
}
