// The server's binary messages (viewer/src/message.h): u32 header length, the JSON
// header, padding to 4 bytes, then the buffers the header lists.
const TYPES = { f32: Float32Array, u32: Uint32Array, u8: Uint8Array };

export function parseMessage(data) {
  const view = new DataView(data);
  const length = view.getUint32(0, true);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(data, 4, length)));
  const base = 4 + length + ((4 - (length % 4)) % 4);
  const buffers = {};
  for (const b of header.buffers || []) {
    const Type = TYPES[b.type];
    if (!Type || base + b.offset + b.bytes > data.byteLength) throw new Error(`bad buffer ${b.name}`);
    buffers[b.name] = new Type(data, base + b.offset, b.count);
  }
  return { header, buffers };
}
